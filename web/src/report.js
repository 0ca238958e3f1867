// The viewer of iilfm's HTML report. The C++ writer (src/report_html.cpp) puts the data in
// <script id="iilfm-data" type="application/json"> and this bundle (three.js included) after it.
// Data: {title, max_points, frames: [frame], sequence?}, each frame the `iilfm detect --json`
// result plus `cloud` (subsampled points) and `overlay_image` (data URI); the page shows the last.
// A recording adds `sequence` (sequence.js) and its `frames` holds the one frame shown in full.
import * as THREE from 'three';

import {axes, decodeBase64, element, fixed, label, matrix, startViewer, table} from './common.js';
import {sequenceSection} from './sequence.js';

const CORNER_COLORS = [0xff3030, 0x30c030, 0x3070ff, 0xffd000];  // top-left .. bottom-left

// Intensity (0..255, display-scaled) to a colour: dark blue - cyan - yellow - white.
function intensityColor(v, out, i) {
  const t = v / 255;
  out[i] = Math.min(1, Math.max(0, 2 * t - 0.6));
  out[i + 1] = Math.min(1, Math.max(0, 1.6 * t));
  out[i + 2] = Math.min(1, Math.max(0, 0.35 + 0.3 * t + Math.max(0, t - 0.8) * 3));
}

function cloudPoints(cloud) {
  const positions = new Float32Array(decodeBase64(cloud.xyz_f32));
  const intensity = new Uint8Array(decodeBase64(cloud.intensity_u8));
  const colors = new Float32Array(positions.length);
  for (let i = 0; i < intensity.length; ++i) intensityColor(intensity[i], colors, 3 * i);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3));
  geometry.computeBoundingSphere();
  const material = new THREE.PointsMaterial({size: 2, sizeAttenuation: false, vertexColors: true});
  return new THREE.Points(geometry, material);
}

function markerObject(m) {
  const group = new THREE.Group();
  const corners = m.corners_lidar.map((c) => (c ? new THREE.Vector3(...c) : null));
  const known = corners.filter((c) => c !== null);
  for (let k = 0; k < corners.length; ++k) {
    const a = corners[k], b = corners[(k + 1) % corners.length];
    if (a && b) {
      const geometry = new THREE.BufferGeometry().setFromPoints([a, b]);
      group.add(new THREE.Line(geometry, new THREE.LineBasicMaterial({color: 0xff9900})));
    }
    if (a) {
      const dot = new THREE.Mesh(
          new THREE.SphereGeometry(0.008, 8, 6),
          new THREE.MeshBasicMaterial({color: CORNER_COLORS[k % 4]}));
      dot.position.copy(a);
      group.add(dot);
    }
  }
  let size = 0.1;
  if (known.length >= 2) size = known[0].distanceTo(known[1]);
  if (m.T_lidar_marker) {
    const frame = axes(size / 2);
    frame.applyMatrix4(matrix(m.T_lidar_marker));
    group.add(frame);
  }
  if (known.length) {
    const centre = known.reduce((s, c) => s.add(c), new THREE.Vector3()).divideScalar(known.length);
    const tag = label(`#${m.id}`, 'label marker-label');
    tag.position.copy(centre);
    group.add(tag);
  }
  return group;
}

function buildScene(frame, container) {
  const scene = new THREE.Scene();
  // Everything measured is in the LiDAR frame; with a pose, that frame is placed in the world.
  const lidar = new THREE.Group();
  if (frame.pose) lidar.applyMatrix4(matrix(frame.pose.T_world_lidar));
  scene.add(lidar);
  const points = cloudPoints(frame.cloud);
  lidar.add(points);
  for (const m of frame.markers) lidar.add(markerObject(m));
  lidar.add(axes(0.5, frame.pose ? 'LiDAR' : 'LiDAR (no pose)'));
  if (frame.pose) scene.add(axes(1, 'world'));

  scene.updateMatrixWorld(true);
  // Look at the markers when there are any, else at the whole cloud, from behind the LiDAR.
  const target = new THREE.Vector3();
  const box = new THREE.Box3();
  for (const m of frame.markers)
    for (const c of m.corners_lidar)
      if (c) box.expandByPoint(new THREE.Vector3(...c).applyMatrix4(lidar.matrixWorld));
  const sphere = points.geometry.boundingSphere.clone().applyMatrix4(lidar.matrixWorld);
  if (box.isEmpty())
    target.copy(sphere.center);
  else
    box.getCenter(target);
  // From beside and above the LiDAR, a quarter of the way towards the target.
  const origin = new THREE.Vector3().applyMatrix4(lidar.matrixWorld);
  const back = origin.clone().sub(target);
  const up = new THREE.Vector3(0, 0, 1);
  if (back.length() < 1e-6) back.set(-1, 0, 0);
  const side = new THREE.Vector3().crossVectors(back, up).normalize();
  const eye = target.clone()
                  .addScaledVector(back, 0.75)
                  .addScaledVector(side, 0.35 * back.length())
                  .addScaledVector(up, 0.25 * back.length());
  const radius = Math.max(1, target.distanceTo(eye));
  return startViewer(container, scene, eye, target, Math.max(100, 4 * (sphere.radius + radius)))
      .canvas;
}

function frameTables(frame) {
  const parts = [];
  parts.push(element('h2', {}, ['Markers']));
  parts.push(table(
      'markers',
      [
        'family', 'id', 'corners observed', 'distance (m)', 'centre, LiDAR frame (m)',
        'fit rms (mm)', 'in map', 'decision margin'
      ],
      frame.markers.map((m) => {
        const known = m.corners_lidar.filter((c) => c);
        const c = known.length ?
            known.reduce((s, p) => s.map((v, i) => v + p[i] / known.length), [0, 0, 0]) :
            null;
        return {
          attrs: {'data-id': m.id, 'data-family': m.family},
          cells: [
            m.family, m.id, `${m.observed.filter((o) => o).length}/${m.observed.length}`,
            c ? fixed(Math.hypot(...c), 3) : '-', c ? c.map((v) => fixed(v, 3)).join(' ') : '-',
            m.T_lidar_marker ? fixed(1000 * m.marker_fit_rms_m, 2) : '-', m.in_map ? 'yes' : 'no',
            fixed(m.decision_margin, 1)
          ],
        };
      })));
  if (!frame.markers.length) parts.push(element('p', {}, ['No marker found.']));

  parts.push(element('h2', {}, ['LiDAR pose in the world']));
  if (frame.pose) {
    const p = frame.pose;
    parts.push(table(
        'pose', ['x y z (m)', 'roll pitch yaw (deg)', 'rms (mm)', 'markers used'], [{
          cells: [
            p.xyz.map((v) => fixed(v, 4)).join(' '), p.rpy_deg.map((v) => fixed(v, 3)).join(' '),
            fixed(1000 * p.rms_m, 2), p.markers_used.join(', ')
          ]
        }]));
  } else {
    parts.push(element('p', {id: 'pose'}, [`No pose: ${frame.pose_missing_reason || 'no map'}.`]));
  }

  parts.push(element('h2', {}, ['Timing']));
  const order = ['read', 'project', 'preprocess', 'detect', 'lift', 'pose', 'total'];
  const stages =
      Object.entries(frame.timing_ms)
          .sort(([a], [b]) => (order.indexOf(a) + 99) % 99 - (order.indexOf(b) + 99) % 99);
  parts.push(table(
      'timing', stages.map(([k]) => k), [{cells: stages.map(([, v]) => `${fixed(v, 2)} ms`)}]));
  return parts;
}

// One frame in full: the 3-D view of its cloud and markers, its tables and its image.
function frameSection(frame, data, report) {
  const cloud = frame.cloud;
  const info = element('p', {class: 'info', id: 'cloud-info'});
  info.textContent =
      `${frame.input.path}: ${frame.input.valid_points} valid points; the 3-D view shows ` +
      (cloud.shown < cloud.total ?
           `${cloud.shown} of them (1 in ${cloud.step}, at most ${data.max_points} to keep ` +
               'this file small)' :
           'all of them') +
      `, coloured by intensity. Image ${frame.image.width}x${frame.image.height} at ` +
      `${frame.image.res_h_deg} x ${frame.image.res_v_deg} deg, threshold ` +
      `${frame.image.threshold}. Drag to orbit, scroll to zoom, right-drag to pan.`;
  report.append(info);

  const view = element('div', {id: 'view', class: 'view'});
  report.append(view);
  try {
    buildScene(frame, view);
  } catch (e) {
    view.textContent = `The 3-D view needs WebGL: ${e.message}`;
    view.classList.add('no-webgl');
  }
  report.append(...frameTables(frame));
  report.append(element('h2', {}, ['Intensity image with detections']));
  report.append(element('img', {
    id: 'overlay',
    src: frame.overlay_image,
    alt: 'preprocessed intensity image with the detections'
  }));
}

function main() {
  const data = JSON.parse(document.getElementById('iilfm-data').textContent);
  const report = document.getElementById('report');
  const frame = data.frames.length ? data.frames[data.frames.length - 1] : null;
  let shownFrame = null, sequence = {};
  if (data.sequence) {
    sequence = sequenceSection(data.sequence, report);
    const seq = data.sequence;
    if (frame) {
      shownFrame = seq.frames[seq.shown].frame;
      report.append(element('h2', {id: 'shown-frame', 'data-frame': shownFrame},
                            [`Frame ${shownFrame} in full`]));
    } else {
      report.append(element('p', {id: 'shown-frame'}, ['No frame had valid points to show.']));
    }
  }
  if (frame) frameSection(frame, data, report);
  window.iilfmReport = {
    ready: true,
    markers: frame ? frame.markers.map((m) => m.id) : [],
    shownFrame,
    ...sequence,
  };
}

main();
