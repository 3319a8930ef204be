// Drawing many bodies cheaply (docs/viewer.md, "Drawing"): the shapes gaitlab sends (boxes and
// cylinders along their x) as one THREE.InstancedMesh per shape, a unit geometry scaled per
// instance to the body's size, with a colour per instance. Hundreds of bodies cost two draw
// calls; a frame's poses are written into the instance matrices without allocating.
// The live view (scene.js) draws robots' bodies with it; the editor shares shapeGeometry.
import * as THREE from 'three';

// a box or a cylinder whose axis is its local x, as gaitlab's bodies and solids are
export function shapeGeometry(shape, size) {
  if (shape === 'cylinder') {
    const g = new THREE.CylinderGeometry(size[1] / 2, size[1] / 2, size[0], 24);
    g.rotateZ(-Math.PI / 2);
    return g;
  }
  return new THREE.BoxGeometry(size[0], size[1], size[2]);
}

// Scaling a unit box by (x, y, z) and a unit cylinder by (length, diameter, diameter) keeps
// their normals exact (a box's are along the axes, a cylinder's side normals are scaled
// uniformly), so one geometry serves every size.
const kUnit = [1, 1, 1];

export class Bodies {
  // material: shared by every instance (its colour is multiplied by the instance's)
  constructor(parent, material) {
    this.parent = parent;
    this.material = material;
    this.meshes = [];       // one InstancedMesh per shape
    this.names = [];
    this.count = 0;
    this.where = null;      // per body: mesh index, instance index
    this.scales = null;     // per body: x, y, z
    this.positions = null;  // per body: x, y, z of the last pose
    this.m = new THREE.Matrix4();
    this.p = new THREE.Vector3();
    this.q = new THREE.Quaternion();
    this.s = new THREE.Vector3();
  }

  // list: [{ name, shape: 'box'|'cylinder', size: [x, y, z], colour: THREE.Color }]
  build(list) {
    this.dispose();
    const shapes = new Map();   // shape -> indices of list
    list.forEach((b, i) => {
      const shape = b.shape === 'cylinder' ? 'cylinder' : 'box';
      if (!shapes.has(shape)) shapes.set(shape, []);
      shapes.get(shape).push(i);
    });
    this.count = list.length;
    this.names = list.map((b) => b.name);
    this.where = new Int32Array(2 * list.length);
    this.scales = new Float32Array(3 * list.length);
    this.positions = new Float64Array(3 * list.length);
    for (const [shape, indices] of shapes) {
      const mesh = new THREE.InstancedMesh(shapeGeometry(shape, kUnit), this.material, indices.length);
      // the bodies move: no bounding volume computed once for culling (it is for picking)
      mesh.frustumCulled = false;
      mesh.name = `bodies (${shape})`;
      mesh.userData.bodies = new Int32Array(indices);
      const k = this.meshes.length;
      indices.forEach((i, j) => {
        const b = list[i];
        this.where[2 * i] = k;
        this.where[2 * i + 1] = j;
        this.scales.set([b.size[0], b.size[1], b.size[2]], 3 * i);
        mesh.setColorAt(j, b.colour);
        // until the first pose: where the body is, at the origin with its size
        this.s.set(b.size[0], b.size[1], b.size[2]);
        mesh.setMatrixAt(j, this.m.compose(this.p.set(0, 0, 0), this.q.identity(), this.s));
      });
      mesh.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
      this.parent.add(mesh);
      this.meshes.push(mesh);
    }
  }

  // poses: x y z qw qx qy qz per body, from `offset` (in numbers); a null (a value JSON cannot
  // hold: the simulation diverged) keeps the body where it was
  setPoses(poses, offset = 0) {
    const { m, p, q, s, where, scales, positions } = this;
    for (let i = 0; i < this.count; ++i) {
      const k = offset + 7 * i;
      if (poses[k] === null || poses[k + 3] === null) continue;
      p.set(poses[k], poses[k + 1], poses[k + 2]);
      q.set(poses[k + 4], poses[k + 5], poses[k + 6], poses[k + 3]);
      s.set(scales[3 * i], scales[3 * i + 1], scales[3 * i + 2]);
      this.meshes[where[2 * i]].setMatrixAt(where[2 * i + 1], m.compose(p, q, s));
      positions[3 * i] = p.x;
      positions[3 * i + 1] = p.y;
      positions[3 * i + 2] = p.z;
    }
    for (const mesh of this.meshes) {
      mesh.instanceMatrix.needsUpdate = true;
      mesh.boundingSphere = null;   // recomputed when a click picks
      mesh.boundingBox = null;
    }
  }

  // body i's centre (its last pose) into out
  position(i, out) {
    return out.set(this.positions[3 * i], this.positions[3 * i + 1], this.positions[3 * i + 2]);
  }

  // the box around every body (their centres, and half their largest size)
  expandBox(box) {
    const v = this.p;
    for (let i = 0; i < this.count; ++i) {
      const r = Math.max(this.scales[3 * i], this.scales[3 * i + 1], this.scales[3 * i + 2]) / 2;
      this.position(i, v);
      box.expandByPoint(v.set(v.x - r, v.y - r, v.z - r));
      this.position(i, v);
      box.expandByPoint(v.set(v.x + r, v.y + r, v.z + r));
    }
    return box;
  }

  // the nearest hit of a raycaster among the bodies: { body (index), distance, point } or null
  pick(raycaster) {
    const hits = raycaster.intersectObjects(this.meshes, false);
    if (hits.length === 0 || hits[0].instanceId === undefined) return null;
    const h = hits[0];
    return { body: h.object.userData.bodies[h.instanceId], distance: h.distance, point: h.point };
  }

  dispose() {
    for (const mesh of this.meshes) {
      this.parent.remove(mesh);
      mesh.geometry.dispose();
      mesh.dispose();
    }
    this.meshes = [];
    this.count = 0;
  }
}
