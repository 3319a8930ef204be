// Contact points in the 3D view: while the "Contact points" box is ticked, gaitlab adds the
// points where bodies touch to every frame (`contacts`: x y z, normal x y z, force N, seven
// numbers each; docs/viewer.md), and they are drawn as red dots, larger for larger forces.
// Unticked, gaitlab sends none and nothing is drawn.
import * as THREE from 'three';

const kMax = 4096;   // points drawn at most
const box = document.getElementById('contacts');
const gaitlab = window.gaitlab;
const dots = new THREE.InstancedMesh(new THREE.SphereGeometry(1, 10, 8),
  new THREE.MeshBasicMaterial({ color: 0xd62828, depthTest: false, transparent: true, opacity: 0.9 }),
  kMax);
dots.count = 0;
dots.renderOrder = 10;
dots.frustumCulled = false;
dots.name = 'contacts';
gaitlab.three.world.add(dots);
gaitlab.contacts = 0;   // points drawn now, for tests

async function send(on) {
  const simulation = gaitlab.scene ? gaitlab.scene.simulation : undefined;
  const token = new URLSearchParams(location.search).get('token');
  await fetch(`api/command${token ? `?token=${encodeURIComponent(token)}` : ''}`, {
    method: 'POST', headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ command: 'contacts', enabled: on, simulation }),
  });
}
box.addEventListener('change', () => send(box.checked));

const m = new THREE.Matrix4();
const q = new THREE.Quaternion();
const s = new THREE.Vector3();
const p = new THREE.Vector3();
let drawn = null;
function update() {
  requestAnimationFrame(update);
  const f = gaitlab.frame;
  if (!f || f === drawn) return;
  drawn = f;
  const state = f.state || {};
  if (state.contacts !== undefined && document.activeElement !== box) box.checked = state.contacts;
  const c = f.contacts || [];
  const n = Math.min(Math.floor(c.length / 7), kMax);
  for (let i = 0; i < n; ++i) {
    const k = i * 7;
    if (c[k] === null) continue;
    p.set(c[k], c[k + 1], c[k + 2]);
    // 3 mm, up to 9 mm for 10 N and more
    const r = 0.003 + 0.006 * Math.min(Math.abs(c[k + 6] || 0) / 10, 1);
    s.set(r, r, r);
    dots.setMatrixAt(i, m.compose(p, q, s));
  }
  dots.count = n;
  dots.instanceMatrix.needsUpdate = true;
  gaitlab.contacts = n;
  gaitlab.three.invalidate();   // the view draws only what changed (scene.js)
}
update();
