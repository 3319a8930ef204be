// The environment editor (docs/viewer.md, "Editing a world"): a top view, a side view (both
// orthographic, with a grid and snapping) and a 3D view of an environment; objects are added,
// moved, resized and turned with the mouse (or typed in the form), robots placed, and the
// world saved. Every edit goes to gaitlab (/api/world/check), where the engine's own validation
// checks it; gaitlab builds the shapes (/api/world/shape) and writes the file (/api/world/save)
// with the engine's writer. `gaitlab edit ENV.xml` opens the page in the editor; under --view
// the "Edit world" button opens it on the shown simulation's world (edit and save only).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { TransformControls } from 'three/addons/controls/TransformControls.js';
import { shapeGeometry } from './bodies.js';

const token = new URLSearchParams(location.search).get('token');
const api = (path) => (token ? `${path}?token=${encodeURIComponent(token)}` : path);
const $ = (id) => document.getElementById(id);
const el = (tag, props = {}, ...kids) => {
  const e = Object.assign(document.createElement(tag), props);
  e.append(...kids);
  return e;
};

// what tests (and curious users) can read: window.gaitlab.editor
const ed = {
  open: false,
  info: null,        // GET /api/world
  env: null,         // the environment being edited (the page's JSON, as gaitlab reads it)
  selected: null,    // { object: i } or { place: i }
  error: null,       // { error, object?, field? } from gaitlab, or null
  checks: 0,         // answers to checks received and shown
  saved: null,       // the last save's answer
  views: {},
};
window.gaitlab = window.gaitlab || {};
window.gaitlab.editor = ed;

async function request(path, body) {
  const r = await fetch(api(path), body === undefined ? {} : {
    method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body),
  });
  let data = {};
  try { data = await r.json(); } catch (e) { data = { error: `gaitlab answered HTTP ${r.status}` }; }
  return { status: r.status, data };
}

// ---------------------------------------------------------------------------------------------
// the page: three views and a panel

const grid = { step: 0.05, angle: 15 };   // snapping: metres, degrees (0: off)

function buildPage() {
  const views = el('div', { id: 'editor-views', hidden: true });
  for (const [name, title] of [['perspective', '3D'], ['top', 'top view (x →, y ↑)'],
    ['side', 'side view (x →, z ↑)']]) {
    const box = el('div', { className: `editor-view editor-${name}` },
      el('canvas', { id: `editor-${name}` }), el('span', { className: 'editor-label' }, title));
    views.appendChild(box);
  }
  document.getElementById('app').appendChild(views);

  const kinds = el('select', { id: 'editor-kind', title: 'What to add' });
  const panel = el('section', { id: 'editor-panel', hidden: true },
    el('h2', {}, 'Edit world'),
    el('div', { className: 'small', id: 'editor-file' }),
    el('div', { className: 'row' }, kinds,
      el('button', { id: 'editor-add', title: 'Add one in the middle of the top view' }, 'Add'),
      el('button', { id: 'editor-delete', title: 'Remove the selected object (Delete)' }, 'Remove')),
    el('div', { className: 'row' },
      ...['translate', 'rotate', 'scale'].map((m, i) => el('label', {},
        el('input', { type: 'radio', name: 'editor-mode', value: m, checked: i === 0 }),
        ` ${['move', 'turn', 'resize'][i]}`))),
    el('div', { className: 'row' },
      el('label', { title: 'Positions and sizes snap to this grid' }, 'snap ',
        el('select', { id: 'editor-snap' },
          ...[['0', 'off'], ['0.01', '1 cm'], ['0.05', '5 cm'], ['0.1', '10 cm']].map(([v, t]) =>
            el('option', { value: v, selected: Number(v) === grid.step }, t)))),
      el('label', { title: 'Turns snap to this angle' }, ' turn ',
        el('select', { id: 'editor-snap-angle' },
          ...[['0', 'off'], ['5', '5°'], ['15', '15°'], ['45', '45°']].map(([v, t]) =>
            el('option', { value: v, selected: Number(v) === grid.angle }, t))))),
    el('select', { id: 'editor-list', size: 8, title: 'The objects and the robots\' places' }),
    el('div', { id: 'editor-form' }),
    el('h3', {}, 'Floor'),
    el('div', { id: 'editor-floor' }),
    el('div', { className: 'row' },
      el('label', {}, 'save as ', el('input', { id: 'editor-name', size: 18 })),
      el('button', { id: 'editor-save', title: 'Check and write the environment file' }, 'Save')),
    el('div', { id: 'editor-status', role: 'status' }),
    el('div', { className: 'row' },
      el('button', { id: 'editor-leave', title: 'Back to the simulation (nothing changes there)' },
        'Leave editor')));
  document.getElementById('panel').prepend(panel);

  const toggle = el('button', { id: 'edit-world', title: 'Edit the world and save it as an environment file' }, 'Edit world');
  const controls = document.querySelector('#controls .row');
  if (controls) controls.appendChild(toggle);
}

// ---------------------------------------------------------------------------------------------
// the three views: each has its own scene (an object has one parent), built from the same
// shapes; the gizmo of each view moves the object of its scene, and the others follow

const objectMaterial = new THREE.MeshStandardMaterial({ color: 0x8e98a6, roughness: 0.8 });
const dynamicMaterial = new THREE.MeshStandardMaterial({ color: 0xb59b6a, roughness: 0.7 });
const selectedMaterial = new THREE.MeshStandardMaterial({ color: 0x4f8fd6, roughness: 0.6 });
const badMaterial = new THREE.MeshStandardMaterial({ color: 0xd64545, roughness: 0.6 });
const robotMaterials = [0xe07b24, 0xc4661a].map((c) => new THREE.MeshStandardMaterial({ color: c, roughness: 0.55 }));

function makeView(name) {
  const canvas = $(`editor-${name}`);
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(name === 'perspective' ? 0xdfe6ee : 0xf4f6f8);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x8d8d8d, 2.2));
  const sun = new THREE.DirectionalLight(0xffffff, 2.0);
  sun.position.set(2, -3, 5);
  scene.add(sun);
  let camera;
  if (name === 'perspective') {
    camera = new THREE.PerspectiveCamera(45, 1, 0.005, 500);
    camera.up.set(0, 0, 1);
  } else {
    camera = new THREE.OrthographicCamera(-1, 1, 1, -1, -200, 200);
    camera.up.set(0, name === 'top' ? 1 : 0, name === 'top' ? 0 : 1);
  }
  const orbit = new OrbitControls(camera, canvas);
  if (name !== 'perspective') {
    orbit.enableRotate = false;
    orbit.screenSpacePanning = true;
    orbit.mouseButtons = { LEFT: THREE.MOUSE.PAN, MIDDLE: THREE.MOUSE.DOLLY, RIGHT: THREE.MOUSE.PAN };
  }
  // grids: 10 cm and 1 m lines in the plane the view looks at
  const grids = new THREE.Group();
  for (const [size, div, c1, c2] of [[20, 200, 0xd5dbe3, 0xd5dbe3], [20, 20, 0x9aa6b5, 0x9aa6b5]]) {
    const g = new THREE.GridHelper(size, div, c1, c2);
    if (name === 'side') g.position.y = 5; else g.rotation.x = Math.PI / 2;
    grids.add(g);
  }
  scene.add(grids);
  if (name === 'perspective') {
    const floor = new THREE.Mesh(new THREE.PlaneGeometry(20, 20),
      new THREE.MeshStandardMaterial({ color: 0xf4f6f8, roughness: 1 }));
    floor.position.z = -0.0005;
    scene.add(floor);
  }
  if (name === 'side') {
    // the floor seen edge on
    const line = new THREE.Mesh(new THREE.BoxGeometry(20, 0.001, 0.004),
      new THREE.MeshBasicMaterial({ color: 0x56606e }));
    line.position.z = -0.002;
    scene.add(line);
  }
  scene.add(new THREE.AxesHelper(0.1));
  const objects = new THREE.Group();
  scene.add(objects);
  const gizmo = new TransformControls(camera, canvas);
  gizmo.setSpace('world');
  if (name === 'top') gizmo.showZ = false;
  if (name === 'side') gizmo.showY = false;
  scene.add(gizmo.getHelper());
  const view = { name, canvas, renderer, scene, camera, orbit, gizmo, objects, groups: [],
    places: [], span: 3 };
  gizmo.addEventListener('dragging-changed', (e) => { orbit.enabled = !e.value; });
  gizmo.addEventListener('objectChange', () => fromGizmo(view, false));
  gizmo.addEventListener('mouseUp', () => fromGizmo(view, true));
  canvas.addEventListener('pointerdown', (e) => pointerDown(view, e));
  return view;
}

function resizeView(v) {
  const w = v.canvas.clientWidth, h = v.canvas.clientHeight;
  if (w === 0 || h === 0) return;
  const pr = v.renderer.getPixelRatio();
  if (v.canvas.width !== Math.floor(w * pr) || v.canvas.height !== Math.floor(h * pr)) {
    v.renderer.setSize(w, h, false);
  }
  if (v.camera.isPerspectiveCamera) {
    v.camera.aspect = w / h;
  } else {
    v.camera.left = -v.span / 2;
    v.camera.right = v.span / 2;
    v.camera.top = v.span * h / w / 2;
    v.camera.bottom = -v.span * h / w / 2;
  }
  v.camera.updateProjectionMatrix();
}

// looks at the whole world: the objects, the robots and a margin
function frameViews() {
  const box = new THREE.Box3();
  const v3 = ed.views.perspective;
  for (const g of [...v3.groups, ...v3.places]) if (g) box.expandByObject(g);
  if (box.isEmpty()) box.set(new THREE.Vector3(-0.5, -0.5, 0), new THREE.Vector3(1, 0.5, 0.2));
  const c = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3());
  const span = Math.max(size.x, size.y, size.z, 1) + 1;
  for (const v of [ed.views.top, ed.views.side]) {
    v.span = span;
    v.camera.zoom = 1;
    if (v.name === 'top') {
      v.camera.position.set(c.x, c.y, 50);
      v.orbit.target.set(c.x, c.y, 0);
    } else {
      v.camera.position.set(c.x, -50, Math.max(c.z, span / 4 - 0.1));
      v.orbit.target.set(c.x, 0, Math.max(c.z, span / 4 - 0.1));
    }
    v.orbit.update();
  }
  v3.orbit.target.copy(c);
  v3.camera.position.copy(c).add(new THREE.Vector3(-0.6, -1, 0.7).multiplyScalar(span * 0.9));
  v3.orbit.update();
}

function draw() {
  requestAnimationFrame(draw);
  if (!ed.open) return;
  for (const v of Object.values(ed.views)) {
    resizeView(v);
    v.orbit.update();
    v.renderer.render(v.scene, v.camera);
  }
}

// ---------------------------------------------------------------------------------------------
// objects: their shapes come from gaitlab (the engine's solids, in the object's own frame)

const shapeCache = new Map();
// the fields that change an object's shape: everything but where it is and its friction
function shapeKey(o) {
  const k = { ...o };
  delete k.position; delete k.yaw; delete k.orientation; delete k.friction; delete k.mass;
  return JSON.stringify(k);
}

function numberOf(i) {
  const kind = ed.env.objects[i].kind;
  let n = 0;
  for (let k = 0; k <= i; ++k) if (ed.env.objects[k].kind === kind) n++;
  return n;
}
const nameOf = (i) => `${ed.env.objects[i].kind} ${numberOf(i)}`;

async function shapeOf(i) {
  const o = ed.env.objects[i];
  const key = shapeKey(o);
  if (shapeCache.has(key)) return shapeCache.get(key);
  const r = await request('api/world/shape', { object: o, number: numberOf(i) });
  if (r.status !== 200) return { error: r.data.error };
  shapeCache.set(key, r.data.solids);
  return r.data.solids;
}

function solidMesh(s, material) {
  let mesh;
  if (s.kind === 'mesh') {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(s.positions, 3));
    g.computeVertexNormals();
    mesh = new THREE.Mesh(g, material);
  } else {
    mesh = new THREE.Mesh(shapeGeometry(s.kind, s.size), material);
    const p = s.pose;
    mesh.position.set(p[0], p[1], p[2]);
    mesh.quaternion.set(p[4], p[5], p[6], p[3]);
  }
  return mesh;
}

function quatOf(o) {
  if (o.orientation) {
    const [w, x, y, z] = o.orientation.map(Number);
    return new THREE.Quaternion(x, y, z, w);
  }
  return new THREE.Quaternion().setFromAxisAngle(new THREE.Vector3(0, 0, 1),
    (Number(o.yaw) || 0) * Math.PI / 180);
}

function placeGroup(g, o) {
  const p = o.position.map(Number);
  g.position.set(p[0] || 0, p[1] || 0, p[2] || 0);
  g.quaternion.copy(quatOf(o));
  g.scale.set(1, 1, 1);
}

// (re)builds object i in every view
async function rebuild(i) {
  const solids = await shapeOf(i);
  for (const v of Object.values(ed.views)) {
    const old = v.groups[i];
    const g = new THREE.Group();
    g.userData = { object: i };
    if (!solids.error) {
      const o = ed.env.objects[i];
      const dynamic = Number(o.mass) > 0;
      for (const s of solids) g.add(solidMesh(s, dynamic ? dynamicMaterial : objectMaterial));
    }
    placeGroup(g, ed.env.objects[i]);
    if (old) v.objects.remove(old);
    v.groups[i] = g;
    v.objects.add(g);
  }
  if (ed.selected && ed.selected.object === i) attachGizmos();
  paint();
}

function rebuildPlaces() {
  for (const v of Object.values(ed.views)) {
    for (const g of v.places) if (g) v.objects.remove(g);
    v.places = ed.env.placements.map((p, i) => {
      const g = new THREE.Group();
      g.userData = { place: i };
      const robot = ed.info.robots.find((r) => r.name === p.robot);
      if (robot) {
        robot.bodies.forEach((b, k) => g.add(solidMesh({ kind: b.shape, size: b.size, pose: b.pose },
          robotMaterials[k % 2])));
      } else {
        // a place for a robot not loaded here (gaitlab edit --robot FILE draws it)
        g.add(new THREE.ArrowHelper(new THREE.Vector3(1, 0, 0), new THREE.Vector3(0, 0, 0.01),
          0.3, 0xe07b24, 0.08, 0.06));
        const m = new THREE.Mesh(new THREE.SphereGeometry(0.03), robotMaterials[0]);
        g.add(m);
      }
      placeGroup(g, p);
      v.objects.add(g);
      return g;
    });
  }
  attachGizmos();
}

// colours: the selected object blue, one gaitlab refused red
function paint() {
  for (const v of Object.values(ed.views)) {
    v.groups.forEach((g, i) => {
      if (!g) return;
      const o = ed.env.objects[i];
      const bad = ed.error && ed.error.object === i;
      const sel = ed.selected && ed.selected.object === i;
      const base = Number(o.mass) > 0 ? dynamicMaterial : objectMaterial;
      g.traverse((m) => { if (m.isMesh) m.material = bad ? badMaterial : sel ? selectedMaterial : base; });
    });
  }
}

function selectedGroup(v) {
  if (!ed.selected) return null;
  return ed.selected.object !== undefined ? v.groups[ed.selected.object] : v.places[ed.selected.place];
}

function attachGizmos() {
  const mode = document.querySelector('input[name=editor-mode]:checked').value;
  for (const v of Object.values(ed.views)) {
    const g = selectedGroup(v);
    // the side view turns nothing (objects turn about z only); places do not resize
    const usable = g && !(mode === 'rotate' && v.name === 'side') &&
      !(mode === 'scale' && ed.selected.place !== undefined);
    if (usable) {
      v.gizmo.setMode(mode);
      v.gizmo.showX = mode !== 'rotate';
      v.gizmo.showY = mode !== 'rotate' && v.name !== 'side';
      v.gizmo.showZ = mode === 'rotate' || v.name !== 'top';
      v.gizmo.setTranslationSnap(grid.step || null);
      v.gizmo.setRotationSnap(grid.angle ? grid.angle * Math.PI / 180 : null);
      v.gizmo.attach(g);
    } else {
      v.gizmo.detach();
    }
  }
}

const snap = (x) => (grid.step ? Math.round(x / grid.step) * grid.step : x);
const mm = (x) => Math.round(x * 1e6) / 1e6;

// the object a view's gizmo (or a drag) moved: into the environment, and into the other views
function fromGizmo(view, done) {
  const g = selectedGroup(view);
  if (!g) return;
  const target = ed.selected.object !== undefined ? ed.env.objects[ed.selected.object]
    : ed.env.placements[ed.selected.place];
  const mode = view.gizmo.mode;
  if (mode === 'translate') {
    target.position = [mm(g.position.x), mm(g.position.y), mm(g.position.z)];
  } else if (mode === 'rotate') {
    const q = g.quaternion;
    if (target.orientation) {
      target.orientation = [q.w, q.x, q.y, q.z].map((v) => Math.round(v * 1e9) / 1e9);
    } else {
      const yaw = 2 * Math.atan2(q.z, q.w) * 180 / Math.PI;
      target.yaw = Math.round(yaw * 1e6) / 1e6;
    }
  } else if (mode === 'scale' && done) {
    resize(target, g.scale.x, g.scale.y, g.scale.z);
  }
  for (const v of Object.values(ed.views)) {
    const other = selectedGroup(v);
    if (other && other !== g) {
      other.position.copy(g.position);
      other.quaternion.copy(g.quaternion);
      other.scale.copy(g.scale);
    }
  }
  if (done) changed(mode === 'scale');
  else showForm();
}

// a resize by factors along the object's own x, y, z, as its fields have it
function resize(o, sx, sy, sz) {
  const s = (v, f) => mm(Math.max(Number(v) * f, 0.001));
  const pick = (a, b) => (Math.abs(a - 1) > Math.abs(b - 1) ? a : b);
  switch (o.kind) {
    case 'box': o.size = o.size.map((v, i) => s(v, [sx, sy, sz][i])); break;
    case 'wall': o.length = s(o.length, sx); o.thickness = s(o.thickness, sy); o.height = s(o.height, sz); break;
    case 'ramp': {
      const h = Number(o.length) * Math.tan(Number(o.slope) * Math.PI / 180) * sz;
      o.length = s(o.length, sx);
      o.width = s(o.width, sy);
      o.slope = Math.round(Math.atan2(h, o.length) * 180 / Math.PI * 1e4) / 1e4;
      break;
    }
    case 'stairs': o.step_depth = s(o.step_depth, sx); o.landing = mm(Number(o.landing) * sx);
      o.width = s(o.width, sy); o.step_height = s(o.step_height, sz); break;
    case 'cylinder':
      if (o.lying) { o.length = s(o.length, sx); o.radius = s(o.radius, pick(sy, sz)); } else {
        o.radius = s(o.radius, pick(sx, sy)); o.length = s(o.length, sz);
      }
      break;
    case 'pipe': o.length = s(o.length, sx); o.radius = s(o.radius, pick(sy, sz)); break;
    case 'rubble': o.length = s(o.length, sx); o.width = s(o.width, sy);
      o.min_height = s(o.min_height, sz); o.max_height = s(o.max_height, sz); break;
    case 'heightfield': o.length = s(o.length, sx); o.width = s(o.width, sy);
      o.max_height = s(o.max_height, sz); break;
    default: break;
  }
}

// dragging an object itself in a view (not the gizmo's handles): it follows the pointer in the
// view's plane, snapped to the grid; a click selects
const raycaster = new THREE.Raycaster();
function pointerAt(view, e) {
  const r = view.canvas.getBoundingClientRect();
  return new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
}
function hit(view, e) {
  raycaster.setFromCamera(pointerAt(view, e), view.camera);
  const found = raycaster.intersectObjects([...view.groups, ...view.places].filter(Boolean), true);
  for (const f of found) {
    let o = f.object;
    while (o && o.userData.object === undefined && o.userData.place === undefined) o = o.parent;
    if (o) return { group: o, point: f.point };
  }
  return null;
}
function planePoint(view, e, through) {
  raycaster.setFromCamera(pointerAt(view, e), view.camera);
  const normal = view.name === 'side' ? new THREE.Vector3(0, 1, 0) : new THREE.Vector3(0, 0, 1);
  const plane = new THREE.Plane().setFromNormalAndCoplanarPoint(normal, through);
  return raycaster.ray.intersectPlane(plane, new THREE.Vector3());
}
function pointerDown(view, e) {
  if (e.button !== 0 || view.gizmo.axis !== null) return;   // the gizmo's handle has it
  const h = hit(view, e);
  if (!h) return;
  select(h.group.userData.object !== undefined ? { object: h.group.userData.object }
    : { place: h.group.userData.place });
  const g = selectedGroup(view);
  const start = planePoint(view, e, g.position);
  const from = g.position.clone();
  let moved = false;
  view.orbit.enabled = false;
  view.gizmo.enabled = false;
  const move = (ev) => {
    const p = planePoint(view, ev, from);
    if (!p || !start) return;
    const d = p.sub(start);
    const q = from.clone().add(d);
    q.x = snap(q.x);
    if (view.name === 'side') q.z = Math.max(snap(q.z), from.z < 0 ? q.z : 0); else q.y = snap(q.y);
    if (view.name === 'top') q.z = from.z;
    if (view.name === 'side') q.y = from.y;
    if (q.distanceTo(g.position) > 0) moved = true;
    g.position.copy(q);
    const keep = view.gizmo.mode;
    view.gizmo.mode = 'translate';
    fromGizmo(view, false);
    view.gizmo.mode = keep;
  };
  const up = () => {
    window.removeEventListener('pointermove', move);
    window.removeEventListener('pointerup', up);
    view.orbit.enabled = true;
    view.gizmo.enabled = true;
    if (moved) {
      const keep = view.gizmo.mode;
      view.gizmo.mode = 'translate';
      fromGizmo(view, true);
      view.gizmo.mode = keep;
    }
  };
  window.addEventListener('pointermove', move);
  window.addEventListener('pointerup', up);
  e.stopPropagation();
}

// ---------------------------------------------------------------------------------------------
// the panel: the list, the selected object's form, the floor, saving

function select(s) {
  ed.selected = s;
  attachGizmos();
  showList();
  showForm();
  paint();
}

function showList() {
  const list = $('editor-list');
  list.textContent = '';
  ed.env.objects.forEach((o, i) => {
    const friction = o.friction !== undefined ? `, friction ${o.friction}` : '';
    list.appendChild(el('option', { value: `o${i}`, selected: ed.selected && ed.selected.object === i },
      `${nameOf(i)}${friction}`));
  });
  ed.env.placements.forEach((p, i) => list.appendChild(el('option',
    { value: `p${i}`, selected: ed.selected && ed.selected.place === i }, `robot ${p.robot} (start)`)));
  for (const r of ed.info.robots) {
    if (!ed.env.placements.some((p) => p.robot === r.name)) {
      list.appendChild(el('option', { value: `r${r.name}` }, `robot ${r.name} (not placed: select to place)`));
    }
  }
}

function input(value, onChange, field) {
  const i = el('input', { value: value === undefined ? '' : String(value), size: 7 });
  i.dataset.field = field;
  i.addEventListener('change', () => onChange(i.value));
  return i;
}

// a form's number as gaitlab gets it: a number when it reads as one, else the text as typed
// (gaitlab says what is wrong with it)
const typed = (t) => (t.trim() !== '' && Number.isFinite(Number(t)) ? Number(t) : t);

function showForm() {
  const form = $('editor-form');
  form.textContent = '';
  if (!ed.selected) {
    form.appendChild(el('p', { className: 'small' }, 'select an object (click it, or in the list), or add one'));
    return;
  }
  const isObject = ed.selected.object !== undefined;
  const target = isObject ? ed.env.objects[ed.selected.object] : ed.env.placements[ed.selected.place];
  const fields = isObject ? ed.info.kinds[target.kind]
    : [{ name: 'position', type: 'vec3', unit: 'm' }, { name: 'orientation', type: 'orientation', unit: '' }];
  form.appendChild(el('h3', {}, isObject ? nameOf(ed.selected.object) : `robot ${target.robot}: where it starts`));
  const bad = ed.error && ((isObject && ed.error.object === ed.selected.object) || (!isObject && !ed.error.object));
  for (const f of fields) {
    const row = el('div', { className: 'editor-field' }, el('label', {}, f.name));
    const shape = f.name !== 'position' && f.name !== 'friction' && f.name !== 'orientation' && f.name !== 'mass';
    const set = (v) => { target[f.name] = v; changed(shape); };
    if (f.type === 'vec3') {
      const v = target[f.name] || [0, 0, 0];
      [0, 1, 2].forEach((k) => row.appendChild(input(v[k], (t) => {
        const copy = [...(target[f.name] || [0, 0, 0])];
        copy[k] = typed(t);
        set(copy);
      }, `${f.name}.${k}`)));
    } else if (f.type === 'orientation') {
      // a turn about z is shown as yaw; any other orientation as w x y z
      const q = (target.orientation || [1, 0, 0, 0]).map(Number);
      if (Math.abs(q[1]) < 1e-12 && Math.abs(q[2]) < 1e-12) {
        const yaw = Math.round(2 * Math.atan2(q[3], q[0]) * 180 / Math.PI * 1e6) / 1e6;
        row.firstChild.textContent = 'yaw';
        row.appendChild(input(yaw, (t) => {
          const a = Number(t) * Math.PI / 360;
          if (!Number.isFinite(a)) { set(['yaw', t]); return; }
          set([Math.cos(a), 0, 0, Math.sin(a)]);
        }, 'yaw'));
        row.appendChild(el('span', { className: 'unit' }, 'deg'));
      } else {
        q.forEach((c, k) => row.appendChild(input(c, (t) => {
          const copy = [...target.orientation];
          copy[k] = typed(t);
          set(copy);
        }, `orientation.${k}`)));
      }
    } else if (f.type === 'flag') {
      const c = el('input', { type: 'checkbox', checked: !!target[f.name] });
      c.dataset.field = f.name;
      c.addEventListener('change', () => set(c.checked));
      row.appendChild(c);
    } else {
      row.appendChild(input(target[f.name], (t) => set(typed(t)), f.name));
    }
    if (f.unit && f.type !== 'orientation') row.appendChild(el('span', { className: 'unit' }, f.unit));
    if (bad && ed.error.field === f.name) row.classList.add('bad');
    form.appendChild(row);
  }
  if (isObject && target.kind === 'heightfield') {
    if (target.image !== undefined) {
      // its image: one of the PNG files of the folder (grey levels scaled to max_height)
      const pick = el('select', {}, ...[...new Set([target.image, ...ed.info.images])].map((n) =>
        el('option', { value: n, selected: n === target.image }, n)));
      pick.dataset.field = 'image';
      pick.addEventListener('change', () => { target.image = pick.value; changed(true); });
      const row = el('div', { className: 'editor-field' }, el('label', {}, 'image'), pick);
      if (bad && ed.error.field === 'image') row.classList.add('bad');
      form.appendChild(row);
      const numbers = el('button', { id: 'editor-heights-numbers', title: 'Give its heights as numbers instead of an image' }, 'heights from numbers');
      numbers.addEventListener('click', () => {
        delete target.image;
        target.heights = flatGrid(5, 5);
        target.length = 0.4;
        target.width = 0.4;
        changed(true);
      });
      form.appendChild(numbers);
    } else if (target.heights !== undefined) {
      form.appendChild(heightsForm(target, bad));
    } else {
      form.appendChild(el('p', { className: 'small' },
        `heights stored in the file (${(target.samples || []).join(' × ')} samples; too many to edit as numbers)`));
    }
  }
}

// rows × columns heights of 0 m
const flatGrid = (rows, columns) => Array.from({ length: rows }, () => new Array(columns).fill(0));

// a heightfield's heights as numbers: one line per row (along y, the first at -width/2), the
// heights of a row along x separated by spaces, in m; and the cell size, which sets the length
// and width. gaitlab checks them (rows of the same length, numbers, at least 2 × 2)
function heightsForm(target, bad) {
  const box = el('div', { className: 'editor-heights' });
  const rows = target.heights.length;
  const columns = rows > 0 && Array.isArray(target.heights[0]) ? target.heights[0].length : 0;
  const cell = columns > 1 ? target.length / (columns - 1) : 0.1;
  const text = el('textarea', { id: 'editor-heights', rows: Math.min(Math.max(rows, 3), 12), cols: 34, spellcheck: false });
  text.value = target.heights.map((r) => (Array.isArray(r) ? r.join(' ') : String(r))).join('\n');
  text.dataset.field = 'heights';
  const cellInput = input(Math.round(cell * 1e6) / 1e6, (t) => {
    const c = typed(t);
    if (typeof c !== 'number' || !(c > 0)) {
      status(`cell size: a positive number of m expected (got '${t}')`, 'error');
      return;
    }
    const n = target.heights.length;
    const m = n > 0 && Array.isArray(target.heights[0]) ? target.heights[0].length : 0;
    target.length = mm((m - 1) * c);
    target.width = mm((n - 1) * c);
    changed(true);
  }, 'cell');
  cellInput.id = 'editor-heights-cell';
  text.addEventListener('change', () => {
    // a word that is not a number goes as typed: gaitlab says where it is
    const lines = text.value.split('\n').map((l) => l.trim()).filter((l) => l !== '');
    const grid = lines.map((l) => l.split(/[\s,;]+/).map(typed));
    const c = Number(cellInput.value) > 0 ? Number(cellInput.value) : cell;
    target.heights = grid;
    if (grid.length > 1 && grid[0].length > 1) {
      target.length = mm((grid[0].length - 1) * c);
      target.width = mm((grid.length - 1) * c);
    }
    changed(true);
  });
  box.append(
    el('div', { className: 'editor-field' }, el('label', {}, 'cell'), cellInput, el('span', { className: 'unit' }, 'm')),
    el('p', { className: 'small', id: 'editor-heights-size' },
      `heights (m): ${rows} rows (along y) × ${columns} columns (along x), a line per row`),
    text);
  if (bad && ed.error.field === 'heights') box.classList.add('bad');
  return box;
}

function showFloor() {
  const box = $('editor-floor');
  box.textContent = '';
  const f = ed.env.floor;
  const on = el('input', { type: 'checkbox', id: 'editor-floor-on', checked: f.enabled !== false });
  on.addEventListener('change', () => { f.enabled = on.checked; changed(false); });
  const friction = input(f.friction, (t) => { f.friction = typed(t); changed(false); }, 'floor.friction');
  friction.id = 'editor-floor-friction';
  const row = el('div', { className: 'editor-field' }, el('label', {}, 'friction'), friction,
    el('label', {}, on, ' floor'));
  // the floor's contact: compliant, with a stiffness and a damping per contact point (empty:
  // the key goes and the engine's default holds), or rigid (then neither; docs/lua-api.md)
  const rigid = el('input', { type: 'checkbox', id: 'editor-floor-rigid', checked: f.rigid === true });
  const rows = [row, el('div', { className: 'editor-field' }, el('label', {}, 'contact'),
    el('label', {}, rigid, ' rigid'))];
  const springs = [];
  for (const [key, unit] of [['stiffness', 'N/m per point'], ['damping', 'N·s/m per point']]) {
    const i = input(f[key], (t) => {
      if (t.trim() === '') delete f[key]; else f[key] = typed(t);
      changed(false);
    }, `floor.${key}`);
    i.id = `editor-floor-${key}`;
    i.placeholder = key === 'stiffness' ? '1e5 (default)' : '60 (default)';
    i.disabled = f.rigid === true;
    springs.push(i);
    rows.push(el('div', { className: 'editor-field' }, el('label', {}, key), i,
      el('span', { className: 'unit' }, unit)));
  }
  rigid.addEventListener('change', () => {
    if (rigid.checked) {
      f.rigid = true;
      delete f.stiffness;
      delete f.damping;
      for (const i of springs) i.value = '';
    } else {
      delete f.rigid;
    }
    for (const i of springs) i.disabled = rigid.checked;
    changed(false);
  });
  if (ed.error && ed.error.field === 'floor') for (const r of rows) r.classList.add('bad');
  box.append(...rows);
}

function status(text, level) {
  const s = $('editor-status');
  s.textContent = text;
  s.className = level;
}

// every change: gaitlab checks the whole world (the engine's validation)
let checking = 0;
async function changed(shape) {
  const n = ++checking;
  const r = await request('api/world/check', { environment: ed.env });
  if (n !== checking) return;   // a newer change is on its way
  ed.error = r.status === 200 ? null : r.data;
  if (ed.error) status(ed.error.error, 'error');
  else if (r.data.warnings && r.data.warnings.length > 0) status(`the engine takes it, but: ${r.data.warnings.join('; ')}`, 'warning');
  else status(`the engine takes it: ${r.data.solids} solid${r.data.solids === 1 ? '' : 's'}`, 'ok');
  if (ed.selected && ed.selected.object !== undefined && (shape || !ed.error)) {
    await rebuild(ed.selected.object);
  }
  if (ed.selected && ed.selected.place !== undefined) {
    for (const v of Object.values(ed.views)) placeGroup(v.places[ed.selected.place], ed.env.placements[ed.selected.place]);
  }
  showList();
  showForm();
  showFloor();
  paint();
  ed.checks++;   // counted once the page shows the answer (status, marked fields, views)
}

async function add() {
  const kind = $('editor-kind').value;
  if (!ed.env) return;
  const o = JSON.parse(JSON.stringify(ed.info.defaults[kind]));
  // in the middle of the top view, on the grid, standing on the floor
  const t = ed.views.top.orbit.target;
  o.position = [mm(snap(t.x)), mm(snap(t.y)), 0];
  if (kind === 'box') o.position[2] = mm(o.size[2] / 2);
  if (kind === 'cylinder') o.position[2] = mm(o.length / 2);
  if (kind === 'heightfield') {
    // a PNG of the folder when there is one (its form can switch to numbers), else numbers
    if (ed.info.images.length > 0) {
      o.image = ed.info.images[0];
    } else {
      delete o.image;
      o.heights = flatGrid(5, 5);
      o.length = 0.4;
      o.width = 0.4;
    }
  }
  // after the others of its kind: the engine numbers them (and the file writes them) that way
  const order = ed.info.order;
  let at = ed.env.objects.length;
  while (at > 0 && order.indexOf(ed.env.objects[at - 1].kind) > order.indexOf(kind)) at--;
  ed.env.objects.splice(at, 0, o);
  for (const v of Object.values(ed.views)) v.groups.splice(at, 0, null);
  renumber();
  select({ object: at });
  await rebuild(at);
  await changed(false);
}

function renumber() {
  for (const v of Object.values(ed.views)) v.groups.forEach((g, i) => { if (g) g.userData.object = i; });
}

async function remove() {
  if (!ed.selected) return;
  if (ed.selected.object !== undefined) {
    const i = ed.selected.object;
    ed.env.objects.splice(i, 1);
    for (const v of Object.values(ed.views)) {
      if (v.groups[i]) v.objects.remove(v.groups[i]);
      v.groups.splice(i, 1);
    }
    renumber();
  } else {
    ed.env.placements.splice(ed.selected.place, 1);
    rebuildPlaces();
  }
  select(null);
  await changed(false);
}

async function save(overwrite = false) {
  const body = { environment: ed.env, source: ed.info.source };
  const name = $('editor-name').value.trim();
  if (name && name !== ed.info.file) body.file = name;
  if (overwrite) body.overwrite = true;
  const r = await request('api/world/save', body);
  if (r.status === 200) {
    ed.saved = r.data;
    ed.error = null;
    status(`saved ${r.data.file} (${r.data.bytes} bytes): gaitlab run loads it`, 'ok');
    paint();
    return;
  }
  ed.error = r.data;
  status(`not saved: ${r.data.error}`, 'error');
  if (r.status === 409 && !/opened again/.test(r.data.error)) {
    const again = el('button', { id: 'editor-overwrite' }, 'Save anyway');
    again.addEventListener('click', () => save(true));
    $('editor-status').append(' ', again);
  }
  showForm();
  showFloor();
  paint();
}

// ---------------------------------------------------------------------------------------------
// opening and leaving

async function openEditor() {
  const r = await request('api/world');
  if (r.status !== 200) {
    status(r.data.error, 'error');
    return false;
  }
  ed.info = r.data;
  ed.env = r.data.environment;
  ed.error = null;
  ed.selected = null;
  ed.open = true;
  document.body.classList.add('editing');
  $('editor-views').hidden = false;
  $('editor-panel').hidden = false;
  $('editor-leave').hidden = ed.info.mode === 'edit';
  $('editor-file').textContent = `${ed.info.exists ? '' : 'new: '}${ed.info.folder}/${ed.info.file}` +
    (ed.info.mode === 'view' ? ' (the simulation runs on as it was)' : '');
  $('editor-name').value = ed.info.file;
  const kinds = $('editor-kind');
  kinds.textContent = '';
  for (const k of ed.info.order) kinds.appendChild(el('option', { value: k }, k));
  if (Object.keys(ed.views).length === 0) {
    for (const name of ['perspective', 'top', 'side']) ed.views[name] = makeView(name);
  }
  for (const v of Object.values(ed.views)) {
    for (const g of [...v.groups, ...v.places]) if (g) v.objects.remove(g);
    v.groups = [];
    v.places = [];
  }
  await Promise.all(ed.env.objects.map((o, i) => rebuild(i)));
  rebuildPlaces();
  for (const v of Object.values(ed.views)) resizeView(v);
  frameViews();
  select(null);
  showFloor();
  status(ed.info.exists ? 'opened' : 'a new environment: Save writes it', 'ok');
  return true;
}

function leave() {
  ed.open = false;
  document.body.classList.remove('editing');
  $('editor-views').hidden = true;
  $('editor-panel').hidden = true;
}

buildPage();
$('edit-world').addEventListener('click', openEditor);
$('editor-leave').addEventListener('click', leave);
$('editor-add').addEventListener('click', add);
$('editor-delete').addEventListener('click', remove);
$('editor-save').addEventListener('click', () => save(false));
$('editor-snap').addEventListener('change', (e) => { grid.step = Number(e.target.value); attachGizmos(); });
$('editor-snap-angle').addEventListener('change', (e) => { grid.angle = Number(e.target.value); attachGizmos(); });
for (const r of document.querySelectorAll('input[name=editor-mode]')) r.addEventListener('change', attachGizmos);
$('editor-list').addEventListener('change', (e) => {
  const v = e.target.value;
  if (v[0] === 'o') select({ object: Number(v.slice(1)) });
  else if (v[0] === 'p') select({ place: Number(v.slice(1)) });
  else {
    // a robot not placed yet: at the origin, along +x
    ed.env.placements.push({ robot: v.slice(1), position: [0, 0, 0], orientation: [1, 0, 0, 0] });
    rebuildPlaces();
    select({ place: ed.env.placements.length - 1 });
    changed(false);
  }
});
// the simulation's keys (space, s, r) do nothing while editing; Delete removes
window.addEventListener('keydown', (e) => {
  if (!ed.open) return;
  if (e.target.tagName === 'INPUT' || e.target.tagName === 'SELECT') return;
  if (e.key === 'Delete') remove();
  e.stopImmediatePropagation();
}, true);
ed.openEditor = openEditor;
ed.add = add;
ed.save = save;
// where a world point is on the page, in a view: for tests and tools
ed.toScreen = (name, x, y, z) => {
  const v = ed.views[name];
  const p = new THREE.Vector3(x, y, z).project(v.camera);
  const r = v.canvas.getBoundingClientRect();
  return { x: r.left + (p.x + 1) / 2 * r.width, y: r.top + (1 - p.y) / 2 * r.height };
};
draw();
// gaitlab edit: the page is the editor
request('api/world').then((r) => {
  if (r.status === 200 && r.data.mode === 'edit') openEditor();
  else if (r.status === 200 && r.data.editable === false) $('edit-world').hidden = true;  // nothing to edit here
});
