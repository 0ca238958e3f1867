// Helpers shared by the frame view (report.js) and the recording view (sequence.js).
import * as THREE from 'three';
import {OrbitControls} from 'three/examples/jsm/controls/OrbitControls.js';
import {CSS2DObject, CSS2DRenderer} from 'three/examples/jsm/renderers/CSS2DRenderer.js';

export function decodeBase64(text) {
  const bytes = atob(text);
  const out = new Uint8Array(bytes.length);
  for (let i = 0; i < bytes.length; ++i) out[i] = bytes.charCodeAt(i);
  return out.buffer;
}

export function element(tag, attrs = {}, children = []) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  for (const c of children) e.append(c);
  return e;
}

export function fixed(v, digits) {
  return v === null || v === undefined ? '-' : Number(v).toFixed(digits);
}

export function table(id, header, rows) {
  const head = element('tr', {}, header.map((h) => element('th', {}, [h])));
  const body = rows.map(
      (r) => element('tr', r.attrs || {}, r.cells.map((c) => element('td', {}, [String(c)]))));
  return element('table', {id}, [element('thead', {}, [head]), element('tbody', {}, body)]);
}

// Matrix4 from the JSON's row-major 4x4.
export function matrix(rows) {
  const m = new THREE.Matrix4();
  m.set(...rows.flat());
  return m;
}

export function label(text, className) {
  const div = element('div', {class: className});
  div.textContent = text;
  return new CSS2DObject(div);
}

export function axes(length, name) {
  const group = new THREE.Group();
  const dirs = [[1, 0, 0, 0xe03030], [0, 1, 0, 0x30b030], [0, 0, 1, 0x3060e0]];
  for (const [x, y, z, color] of dirs) {
    const geometry = new THREE.BufferGeometry().setFromPoints(
        [new THREE.Vector3(0, 0, 0), new THREE.Vector3(x * length, y * length, z * length)]);
    group.add(new THREE.Line(geometry, new THREE.LineBasicMaterial({color})));
  }
  if (name) group.add(label(name, 'label frame-label'));
  return group;
}

// A WebGL view of `scene` in `container` (z up), orbiting `target` from `eye`, with CSS labels;
// it renders on demand (orbit, resize, or the returned render()).
export function startViewer(container, scene, eye, target, far) {
  const width = container.clientWidth, height = container.clientHeight;
  const renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setSize(width, height);
  renderer.setClearColor(0x10141c);
  container.append(renderer.domElement);
  const labels = new CSS2DRenderer();
  labels.setSize(width, height);
  labels.domElement.className = 'labels';
  container.append(labels.domElement);

  const camera = new THREE.PerspectiveCamera(50, width / height, 0.01, far);
  camera.up.set(0, 0, 1);
  camera.position.copy(eye);
  camera.updateProjectionMatrix();
  const controls = new OrbitControls(camera, labels.domElement);
  controls.target.copy(target);
  controls.update();

  const render = () => {
    renderer.render(scene, camera);
    labels.render(scene, camera);
  };
  controls.addEventListener('change', render);
  window.addEventListener('resize', () => {
    const w = container.clientWidth, h = container.clientHeight;
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    renderer.setSize(w, h);
    labels.setSize(w, h);
    render();
  });
  render();
  return {canvas: renderer.domElement, render};
}
