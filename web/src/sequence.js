// The recording part of the report: the LiDAR trajectory in the world with the mapped markers,
// x/y/z against time, and every frame's detections (slider and table, one frame selected).
// Data (src/report_html.cpp, HtmlSequenceReport): {frames: [summary], keys: ["family/id"],
// map: [{key, id, corners_world}], shown: index of the frame shown in full or null}; a summary is
// {frame, time, markers: [index into keys], ms, xyz?, rpy?, rms_mm?, used?, why?, window?}.
import * as THREE from 'three';

import {axes, element, fixed, label, startViewer, table} from './common.js';

const SVG = 'http://www.w3.org/2000/svg';
const AXIS_COLORS = ['#e03030', '#30a030', '#3060e0'];

function svg(tag, attrs = {}) {
  const e = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  return e;
}

// Blue (start) to yellow (end) along the recording.
function timeColor(t) {
  return new THREE.Color().setHSL(0.62 - 0.48 * t, 0.85, 0.5 + 0.1 * t);
}

// R = Rz(yaw) Ry(pitch) Rx(roll), as the JSON's rpy_deg: three.js's 'ZYX' Euler order.
function poseMatrix(s) {
  const d = Math.PI / 180;
  const m = new THREE.Matrix4().makeRotationFromEuler(
      new THREE.Euler(s.rpy[0] * d, s.rpy[1] * d, s.rpy[2] * d, 'ZYX'));
  m.setPosition(...s.xyz);
  return m;
}

function trajectoryView(seq, container) {
  const scene = new THREE.Scene();
  const posed = seq.frames.filter((s) => s.xyz);
  const box = new THREE.Box3();
  const n = Math.max(1, seq.frames.length - 1);
  if (posed.length) {
    const positions = posed.map((s) => new THREE.Vector3(...s.xyz));
    positions.forEach((p) => box.expandByPoint(p));
    const colors = [];
    for (const s of posed) colors.push(...timeColor(seq.frames.indexOf(s) / n).toArray());
    const line = new THREE.BufferGeometry().setFromPoints(positions);
    line.setAttribute('color', new THREE.Float32BufferAttribute(colors, 3));
    scene.add(new THREE.Line(line, new THREE.LineBasicMaterial({vertexColors: true})));
    const dots = line.clone();
    scene.add(new THREE.Points(
        dots, new THREE.PointsMaterial({size: 5, sizeAttenuation: false, vertexColors: true})));
  }
  const outlines = new Map();  // key -> material, to highlight the selected frame's markers
  const seen = new Set(seq.keys);
  for (const m of seq.map) {
    const corners = m.corners_world.map((c) => new THREE.Vector3(...c));
    corners.forEach((c) => box.expandByPoint(c));
    const material = new THREE.LineBasicMaterial({color: 0x8a93a6});
    scene.add(new THREE.LineLoop(new THREE.BufferGeometry().setFromPoints(corners), material));
    outlines.set(m.key, material);
    if (!seen.has(m.key)) continue;  // labels for all of a large map would hide each other
    const tag = label(`#${m.id}`, 'label map-label');
    tag.position.copy(corners.reduce((s, c) => s.add(c), new THREE.Vector3()).divideScalar(4));
    scene.add(tag);
  }
  scene.add(axes(0.5, 'world'));
  box.expandByPoint(new THREE.Vector3());
  const lidar = axes(0.3, 'LiDAR');
  lidar.matrixAutoUpdate = false;
  lidar.visible = false;
  scene.add(lidar);

  const target = box.getCenter(new THREE.Vector3());
  const size = Math.max(1, box.getSize(new THREE.Vector3()).length());
  const eye = target.clone().add(new THREE.Vector3(-0.45, -0.7, 0.55).multiplyScalar(size));
  const view = startViewer(container, scene, eye, target, 50 * size);
  const show = (summary) => {
    lidar.visible = Boolean(summary.xyz);
    if (summary.xyz) lidar.matrix.copy(poseMatrix(summary));
    const now = new Set(summary.markers.map((k) => seq.keys[k]));
    for (const [key, material] of outlines) material.color.set(now.has(key) ? 0x40e070 : 0x8a93a6);
    view.render();
  };
  return {show, outlines: outlines.size};
}

// x, y and z of the LiDAR against time, one small plot each; gaps where a frame has no pose.
function positionPlots(seq, container) {
  const t0 = seq.frames[0].time;
  const tEnd = Math.max(seq.frames[seq.frames.length - 1].time - t0, 1e-9);
  const W = 360, H = 150, L = 52, R = 8, T = 10, B = 26;
  const cursors = [];
  for (let axis = 0; axis < 3; ++axis) {
    const values = seq.frames.filter((s) => s.xyz).map((s) => s.xyz[axis]);
    let lo = Math.min(...values), hi = Math.max(...values);
    if (hi - lo < 0.01) [lo, hi] = [(lo + hi) / 2 - 0.005, (lo + hi) / 2 + 0.005];
    const px = (t) => L + (W - L - R) * (t - t0) / tEnd;
    const py = (v) => T + (H - T - B) * (hi - v) / (hi - lo);
    const plot = svg('svg', {class: 'plot', id: `plot-${'xyz'[axis]}`, viewBox: `0 0 ${W} ${H}`,
                             width: W, height: H});
    plot.append(svg('rect', {x: L, y: T, width: W - L - R, height: H - T - B, class: 'plot-area'}));
    // Runs of consecutive frames with a pose, one polyline each.
    let run = [];
    const flush = () => {
      if (run.length > 1)
        plot.append(svg('polyline', {points: run.join(' '), stroke: AXIS_COLORS[axis],
                                     fill: 'none', 'stroke-width': 1.5}));
      else if (run.length === 1) {
        const [x, y] = run[0].split(',');
        plot.append(svg('circle', {cx: x, cy: y, r: 1.5, fill: AXIS_COLORS[axis]}));
      }
      run = [];
    };
    for (const s of seq.frames) {
      if (s.xyz) run.push(`${px(s.time).toFixed(1)},${py(s.xyz[axis]).toFixed(1)}`);
      else flush();
    }
    flush();
    const text = (x, y, content, anchor) => {
      const e = svg('text', {x, y, 'text-anchor': anchor, class: 'plot-text'});
      e.textContent = content;
      plot.append(e);
    };
    text(L - 4, T + 9, fixed(hi, 3), 'end');
    text(L - 4, H - B, fixed(lo, 3), 'end');
    text(L - 4, (H - B + T) / 2 + 4, `${'xyz'[axis]} (m)`, 'end');
    text(L, H - 8, '0 s', 'start');
    text(W - R, H - 8, `${fixed(tEnd, 1)} s`, 'end');
    const cursor = svg('line', {y1: T, y2: H - B, class: 'plot-cursor'});
    plot.append(cursor);
    cursors.push({cursor, px});
    container.append(plot);
  }
  return (summary) => {
    for (const {cursor, px} of cursors) {
      cursor.setAttribute('x1', px(summary.time));
      cursor.setAttribute('x2', px(summary.time));
    }
  };
}

function frameCells(seq, s) {
  const t0 = seq.frames[0].time;
  return [
    s.frame, fixed(s.time - t0, 3), s.markers.length,
    s.markers.map((k) => seq.keys[k].split('/').pop()).join(' ') || '-',
    s.xyz ? s.xyz.map((v) => fixed(v, 3)).join(' ') : `- (${s.why || 'no pose'})`,
    s.rpy ? s.rpy.map((v) => fixed(v, 2)).join(' ') : '-', s.xyz ? fixed(s.rms_mm, 2) : '-',
    s.xyz ? s.used : '-', fixed(s.ms, 1)
  ];
}

const FRAME_HEADER = [
  'frame', 'time (s)', 'markers', 'ids', 'LiDAR x y z (m)', 'roll pitch yaw (deg)', 'rms (mm)',
  'markers used', 'total (ms)'
];

// Appends the recording's sections to `report`; returns what the browser test checks.
export function sequenceSection(seq, report) {
  const frames = seq.frames;
  const withMarkers = frames.filter((s) => s.markers.length).length;
  const posed = frames.filter((s) => s.xyz).length;
  const duration = frames[frames.length - 1].time - frames[0].time;
  const windowFrames = frames[0].window ? frames[0].window[1] - frames[0].window[0] + 1 : 1;
  report.append(element('h2', {}, ['Recording']));
  const info = element('p', {class: 'info', id: 'sequence-info'});
  info.textContent =
      `${frames.length} results over ${fixed(duration, 2)} s` +
      (windowFrames > 1 ? ` (windows of ${windowFrames} frames)` : '') +
      `: markers in ${withMarkers}, LiDAR pose in ${posed}. ` +
      `${seq.keys.length} distinct markers seen, ${seq.map.length} in the map.`;
  report.append(info);

  let showTrajectory = () => {};
  let mapOutlines = 0;
  let showPlots = () => {};
  if (posed || seq.map.length) {
    report.append(element('h2', {}, ['LiDAR trajectory in the world']));
    const note = element('p', {class: 'info'});
    note.textContent = 'Coloured blue (start) to yellow (end); map markers grey (labelled when ' +
        'the recording detected them), those the selected frame detected green; the LiDAR axes ' +
        'at the selected frame. Drag to orbit, scroll to zoom, right-drag to pan.';
    report.append(note);
    const view = element('div', {id: 'trajectory-view', class: 'view'});
    report.append(view);
    try {
      const trajectory = trajectoryView(seq, view);
      showTrajectory = trajectory.show;
      mapOutlines = trajectory.outlines;
    } catch (e) {
      view.textContent = `The 3-D view needs WebGL: ${e.message}`;
      view.classList.add('no-webgl');
    }
  }
  if (posed) {
    const plots = element('div', {id: 'plots'});
    report.append(plots);
    showPlots = positionPlots(seq, plots);
  } else {
    report.append(element('p', {id: 'no-trajectory'},
                          ['No frame has a LiDAR pose (it needs --map and mapped markers).']));
  }

  report.append(element('h2', {}, ['Frames']));
  const slider = element('input', {
    id: 'frame-slider',
    type: 'range',
    min: 0,
    max: frames.length - 1,
    value: seq.shown ?? frames.length - 1,
    'aria-label': 'selected frame'
  });
  const detail = element('div', {id: 'frame-detail'});
  report.append(element('div', {class: 'slider-row'}, [slider]), detail);
  const list = table('frames', FRAME_HEADER, frames.map((s) => ({
                       attrs: {
                         'data-frame': s.frame,
                         'data-ids': s.markers.map((k) => seq.keys[k]).join(' ')
                       },
                       cells: frameCells(seq, s)
                     })));
  report.append(element('div', {class: 'frames-scroll'}, [list]));
  const rows = list.querySelectorAll('tbody tr');

  let selected = null;
  const select = (index) => {
    const s = frames[index];
    if (selected !== null) rows[selected].classList.remove('selected');
    selected = index;
    rows[index].classList.add('selected');
    slider.value = index;
    detail.replaceChildren(
        table('frame-selected', FRAME_HEADER, [{cells: frameCells(seq, s)}]),
        element('p', {class: 'info'},
                [s.markers.length ? `markers: ${s.markers.map((k) => seq.keys[k]).join(', ')}` :
                                    'no marker found']));
    showTrajectory(s);
    showPlots(s);
  };
  slider.addEventListener('input', () => {
    select(Number(slider.value));
    rows[selected].scrollIntoView({block: 'nearest'});
  });
  rows.forEach((row, i) => row.addEventListener('click', () => select(i)));
  select(Number(slider.value));
  return {mapOutlines};
}
