// SPDX-License-Identifier: MIT
// The dsm report page: a 3D view of a run's map (points, keyframe trajectory with camera frustums,
// aligned ground truth, covisibility links) and plots of its statistics. The data come from the
// page itself (<script id="dsm-data" type="application/json">, written by `dsm run` and
// `dsm report`) or, in the live viewer (`dsm run --view`), from a WebSocket that sends the same
// document again as the run goes on. Data layout: src/dsm/run/report.h.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { drawPlot } from './plot.js';
import { STYLE } from './style.js';

function decodeBase64(text, Type) {
  const bytes = Uint8Array.from(atob(text || ''), (c) => c.charCodeAt(0));
  return new Type(bytes.buffer, 0, bytes.byteLength / Type.BYTES_PER_ELEMENT);
}

function element(tag, attributes = {}, parent = null, text = null) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attributes)) e.setAttribute(k, v);
  if (text !== null) e.textContent = text;
  if (parent) parent.appendChild(e);
  return e;
}

// Line segments through consecutive positions [[x, y, z], ...].
function polyline(positions, color) {
  const geometry = new THREE.BufferGeometry().setFromPoints(positions.map((p) => new THREE.Vector3(...p)));
  return new THREE.Line(geometry, new THREE.LineBasicMaterial({ color }));
}

function segments(pairs, color, opacity = 1) {
  const geometry = new THREE.BufferGeometry().setFromPoints(pairs.flat().map((p) => new THREE.Vector3(...p)));
  return new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color, transparent: opacity < 1, opacity }));
}

// A camera frustum of depth `size` at pose (p, q: world_from_cam), as 8 segments.
function frustumPairs(p, q, size, aspect) {
  const pose = new THREE.Matrix4().compose(new THREE.Vector3(...p), new THREE.Quaternion(...q), new THREE.Vector3(1, 1, 1));
  const w = 0.5 * size * aspect, h = 0.5 * size;
  const c = new THREE.Vector3(0, 0, 0).applyMatrix4(pose);
  const corners = [[-w, -h], [w, -h], [w, h], [-w, h]].map(([x, y]) => new THREE.Vector3(x, y, size).applyMatrix4(pose));
  const pairs = [];
  for (let i = 0; i < 4; ++i) {
    pairs.push([c.toArray(), corners[i].toArray()]);
    pairs.push([corners[i].toArray(), corners[(i + 1) % 4].toArray()]);
  }
  return pairs;
}

class MapView {
  constructor(container) {
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setClearColor(0x15181d);
    container.appendChild(this.renderer.domElement);
    this.renderer.domElement.id = 'map-canvas';
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(50, 1, 0.001, 1e4);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.layers = {};
    this.container = container;
    this.fitted = false;
    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
    const loop = () => {
      this.controls.update();
      this.renderer.render(this.scene, this.camera);
      requestAnimationFrame(loop);
    };
    loop();
  }

  resize() {
    const w = this.container.clientWidth || 800, h = this.container.clientHeight || 500;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
  }

  setLayer(name, object) {
    if (this.layers[name]) {
      this.scene.remove(this.layers[name]);
      this.layers[name].traverse((o) => o.geometry && o.geometry.dispose());
    }
    this.layers[name] = object;
    if (object) {
      object.visible = this.visible(name);
      this.scene.add(object);
    }
  }

  visible(name) {
    const box = document.getElementById('layer-' + name);
    return !box || box.checked;
  }

  show(map, camera) {
    const xyz = decodeBase64(map.points.xyz, Float32Array);
    const grey = decodeBase64(map.points.grey, Uint8Array);
    const colours = new Float32Array(xyz.length);
    for (let i = 0; i < grey.length; ++i) colours[3 * i] = colours[3 * i + 1] = colours[3 * i + 2] = 0.25 + 0.75 * grey[i] / 255;
    // A map loaded from a map file (dsm run --load-map): its points first, tinted blue; those the
    // run added in grey.
    for (let i = 0; i < Math.min(map.points.loaded || 0, grey.length); ++i) {
      colours[3 * i] *= 0.45;
      colours[3 * i + 1] *= 0.7;
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(xyz, 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
    geometry.computeBoundingSphere();
    const centres = map.keyframes.map((k) => k.p);
    // Sizes from the scene: frustums a fraction of the keyframes' extent.
    const box = new THREE.Box3().setFromPoints(centres.map((p) => new THREE.Vector3(...p)));
    if (xyz.length) box.union(new THREE.Box3().setFromBufferAttribute(geometry.getAttribute('position')));
    const extent = Math.max(box.getSize(new THREE.Vector3()).length(), 1e-6);
    const sizes = { points: Math.max(extent * 0.002, 1e-6) };
    this.setLayer('points', new THREE.Points(geometry, new THREE.PointsMaterial({ size: sizes.points, vertexColors: true })));
    this.setLayer('trajectory', centres.length > 1 ? polyline(centres, 0xff9f1c) : null);
    const aspect = camera ? camera.width / camera.height : 4 / 3;
    const frustums = map.keyframes.flatMap((k) => frustumPairs(k.p, k.q, extent * 0.015, aspect));
    this.setLayer('frustums', frustums.length ? segments(frustums, 0xffbf69) : null);
    this.setLayer('groundtruth', map.groundtruth && map.groundtruth.length > 1
      ? polyline(map.groundtruth.map((r) => r.slice(1, 4)), 0x2ec4b6) : null);
    const byId = new Map(map.keyframes.map((k) => [k.id, k.p]));
    const links = (map.covisibility || []).filter(([a, b]) => byId.has(a) && byId.has(b)).map(([a, b]) => [byId.get(a), byId.get(b)]);
    this.setLayer('covisibility', links.length ? segments(links, 0x5e9cff, 0.45) : null);
    if (!this.fitted) this.fit(box);
    this.extent = extent;
    this.aspect = aspect;
  }

  // The live camera (dsm run --view): a red frustum, twice a keyframe's size.
  showCurrent(current) {
    const pairs = current ? frustumPairs(current.p, current.q, (this.extent || 1) * 0.03, this.aspect || 4 / 3) : [];
    this.setLayer('current', pairs.length ? segments(pairs, 0xff4d4d) : null);
  }

  fit(box) {
    if (box.isEmpty()) return;
    const centre = box.getCenter(new THREE.Vector3());
    const radius = Math.max(box.getSize(new THREE.Vector3()).length() * 0.5, 1e-3);
    this.controls.target.copy(centre);
    // Cameras look along +z with y down: view from behind and above the first keyframe's side.
    this.camera.up.set(0, -1, 0);
    this.camera.position.copy(centre).add(new THREE.Vector3(0.6, -1.2, -1.6).normalize().multiplyScalar(radius * 2.2));
    this.camera.near = radius * 1e-3;
    this.camera.far = radius * 100;
    this.camera.updateProjectionMatrix();
    this.fitted = true;
  }
}

const PLOTS = [
  { id: 'plot-error', title: 'Position error after Sim(3) alignment (mm) over time (s)',
    series: (d) => (d.errors || []).map((e, i) => ({ x: e.t, y: e.error_mm, color: i ? '#9d4edd' : '#2ec4b6', label: `map ${i}` })) },
  { id: 'plot-tracking', title: 'Tracking time per frame (ms) over the frame index',
    series: (d) => [{ x: d.per_frame?.frame, y: d.per_frame?.tracking_ms, color: '#ff9f1c', label: 'tracking ms' }],
    bands: (d) => d.lost_episodes || [] },
  { id: 'plot-pba', title: 'Bundle adjustment time per keyframe (ms) over the frame index',
    series: (d) => [{ x: d.per_keyframe?.frame, y: d.per_keyframe?.pba_ms, color: '#5e9cff', label: 'PBA ms' }] },
  { id: 'plot-points', title: 'Points created and re-observations per keyframe over the frame index',
    series: (d) => [
      { x: d.per_keyframe?.frame, y: d.per_keyframe?.points_created, color: '#e9c46a', label: 'points created' },
      { x: d.per_keyframe?.frame, y: d.per_keyframe?.reobservations, color: '#e76f51', label: 're-observations' }],
    bands: (d) => [...(d.loops_closed || []), ...(d.maps_merged || [])].map((l) => [l.frame, l.frame]) },
];

function summaryText(d) {
  const s = d.summary;
  const parts = [`${s.frames_tracked}/${s.frames} frames tracked`, `${s.keyframes} keyframes`, `${s.map_points} points`,
    `mode ${s.mode}`, `pace ${s.pace}`];
  if (s.frames_per_second) parts.push(`${s.frames_per_second.toFixed(1)} fps`);
  if (s.realtime_factor) parts.push(`${s.realtime_factor.toFixed(2)}x real time`);
  if (s.keyframe_ate_mm !== undefined && s.keyframe_ate_mm !== null) parts.push(`keyframe ATE ${s.keyframe_ate_mm.toFixed(2)} mm`);
  if (s.frames_lost) parts.push(`${s.frames_lost} frames lost, ${s.relocalisations} relocalised`);
  if (d.maps.length > 1) parts.push(`${d.maps.length} maps`);
  if (s.map_loaded) parts.push(`loaded map: ${s.map_loaded.keyframes} keyframes, ${s.map_loaded.points} points (blue)`);
  if (s.interrupted) parts.push('interrupted');
  if (s.state) parts.push(s.state);
  return parts.join(' · ');
}

class Report {
  constructor() {
    element('style', {}, document.head, STYLE);
    const header = element('header', {}, document.body);
    this.title = element('h1', {}, header);
    this.summary = element('p', { id: 'summary' }, header);
    const main = element('main', {}, document.body);
    const viewBox = element('section', { id: 'view' }, main);
    const controls = element('div', { id: 'layers' }, viewBox);
    for (const [name, label] of [['points', 'points'], ['trajectory', 'keyframes'], ['frustums', 'cameras'],
      ['groundtruth', 'ground truth'], ['covisibility', 'covisibility']]) {
      const l = element('label', {}, controls);
      const box = element('input', { type: 'checkbox', id: 'layer-' + name, checked: '' }, l);
      l.appendChild(document.createTextNode(' ' + label));
      box.addEventListener('change', () => { if (this.view.layers[name]) this.view.layers[name].visible = box.checked; });
    }
    this.mapSelect = element('select', { id: 'map-select' }, controls);
    this.mapSelect.addEventListener('change', () => { this.view.fitted = false; this.showMap(); });
    const canvasBox = element('div', { id: 'canvas-box' }, viewBox);
    this.view = new MapView(canvasBox);
    const plots = element('section', { id: 'plots' }, main);
    this.plots = PLOTS.map((p) => {
      const figure = element('figure', {}, plots);
      element('figcaption', {}, figure, p.title);
      return { ...p, canvas: element('canvas', { id: p.id, width: 560, height: 220 }, figure) };
    });
    this.lost = element('p', { id: 'lost' }, plots);
    this.loops = element('p', { id: 'loops' }, plots);
  }

  update(data) {
    this.data = data;
    document.title = `dsm report: ${data.title}`;
    this.title.textContent = data.title;
    this.summary.textContent = summaryText(data);
    if (this.mapSelect.options.length !== data.maps.length) {
      this.mapSelect.replaceChildren(...data.maps.map((m, i) => new Option(`map ${i} (${m.dir})`, i)));
      this.mapSelect.style.display = data.maps.length > 1 ? '' : 'none';
    }
    this.showMap();
    this.view.showCurrent(data.current);
    for (const p of this.plots) {
      const series = p.series(data).filter((s) => s.x && s.x.length);
      p.canvas.dataset.points = series.reduce((n, s) => n + s.x.length, 0);
      drawPlot(p.canvas, series, p.bands ? p.bands(data) : []);
      p.canvas.closest('figure').style.display = series.length ? '' : 'none';
    }
    const lost = data.lost_episodes || [];
    this.lost.textContent = lost.length
      ? 'Lost episodes (first–last frame): ' + lost.map(([a, b]) => `${a}–${b}`).join(', ') +
        ` · ${data.summary.relocalisations} relocalised` : '';
    const loops = data.loops_closed || [];
    this.loops.textContent = loops.length
      ? 'Loops closed (marked in the points plot): ' + loops.map((l) =>
        `frame ${l.frame} with keyframe ${l.candidate_keyframe} (moved ${(100 * l.translation_share).toFixed(2)}% of the ` +
        `path, ${l.rotation_deg.toFixed(2)}°, scale ${l.scale.toFixed(3)})`).join('; ') : '';
    const merges = data.maps_merged || [];
    if (merges.length) {
      this.loops.textContent += (loops.length ? ' · ' : '') + 'Maps merged (marked in the points plot): ' +
        merges.map((m) => `map ${m.map} at frame ${m.frame} (${m.keyframes} keyframes, ${m.points} points, ` +
          `scale ${m.scale.toFixed(3)})`).join('; ');
    }
  }

  showMap() {
    const map = this.data.maps[Number(this.mapSelect.value) || 0];
    if (map) this.view.show(map, this.data.camera);
  }
}

function start() {
  const report = new Report();
  window.dsmReport = report;
  const embedded = document.getElementById('dsm-data');
  if (embedded && embedded.textContent.trim()) report.update(JSON.parse(embedded.textContent));
  // The live viewer: the same document pushed again as the run goes on.
  if (location.protocol.startsWith('http') && document.body.dataset.live === '1') {
    const status = element('span', { id: 'live-status' }, document.querySelector('header'));
    let updates = 0;
    const connect = () => {
      const socket = new WebSocket(`ws://${location.host}/ws`);
      socket.onopen = () => { status.textContent = 'live: connected'; };
      socket.onmessage = (event) => {
        report.update(JSON.parse(event.data));
        status.textContent = `live: connected, update ${++updates}`;
        status.dataset.updates = updates;
      };
      socket.onclose = () => {
        status.textContent = 'live: the run has ended or the connection is lost (report.html is in the output folder)';
        setTimeout(connect, 2000);
      };
    };
    connect();
  }
}

if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', start);
else start();
