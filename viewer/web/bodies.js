// Drawing many bodies cheaply (docs/viewer.md, "Drawing many bodies fast"): every robot body
// (boxes and cylinders along their x, as gaitlab sends them) in ONE mesh drawn with one draw
// call. The mesh holds each body's own shape at its size and in its colour, in the body's
// frame, and a per-vertex body number; the vertex shader moves each vertex by its body's pose,
// read from a small float texture (a position and a quaternion per body) that a frame rewrites:
// 32 bytes a body, nothing allocated. Software WebGL (SwiftShader) draws this 5-6 ms a frame
// faster than 360 instances of an InstancedMesh (docs/performance.md §9).
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

const kUnit = [1, 1, 1];
// bodies per row of the pose texture (two texels each: x y z -, qx qy qz qw)
const kPerRow = 512;

// the vertex shader's part: the body's pose from the texture, applied to the vertex and its
// normal in the body's frame (the mesh itself stays at the origin)
const kShaderHead = /* glsl */`
uniform highp sampler2D bodyPoses;
attribute float body;
vec3 bodyTurn(vec4 q, vec3 v) { return v + 2.0 * cross(q.xyz, cross(q.xyz, v) + q.w * v); }
`;
const kShaderNormal = /* glsl */`
#include <beginnormal_vertex>
int bodyIndex = int(body + 0.5);
ivec2 bodyTexel = ivec2(2 * (bodyIndex % ${kPerRow}), bodyIndex / ${kPerRow});
vec3 bodyPosition = texelFetch(bodyPoses, bodyTexel, 0).xyz;
vec4 bodyQuaternion = texelFetch(bodyPoses, bodyTexel + ivec2(1, 0), 0);
objectNormal = bodyTurn(bodyQuaternion, objectNormal);
`;
const kShaderPosition = /* glsl */`
#include <begin_vertex>
transformed = bodyTurn(bodyQuaternion, transformed) + bodyPosition;
`;

export class Bodies {
  // material: the look of the bodies (a lit material; Bodies draws with a copy of it that
  // takes the colours per body and moves the vertices by the poses)
  constructor(parent, material) {
    this.parent = parent;
    this.uniforms = { bodyPoses: { value: null } };
    this.material = material.clone();
    this.material.vertexColors = true;
    this.material.onBeforeCompile = (shader) => {
      shader.uniforms.bodyPoses = this.uniforms.bodyPoses;
      shader.vertexShader = shader.vertexShader
        .replace('#include <common>', `#include <common>\n${kShaderHead}`)
        .replace('#include <beginnormal_vertex>', kShaderNormal)
        .replace('#include <begin_vertex>', kShaderPosition);
    };
    this.material.customProgramCacheKey = () => 'gaitlab-bodies';
    this.meshes = [];       // the one mesh (an array: empty before the first scene)
    this.names = [];
    this.count = 0;
    this.shapes = null;     // per body: 0 box, 1 cylinder
    this.scales = null;     // per body: x, y, z
    this.positions = null;  // per body: x, y, z of the last pose
    this.poses = null;      // the pose texture's data: 8 floats per body
    this.texture = null;
    // picking: each body's shape posed in turn (three.js's own ray-triangle test)
    this.probes = [new THREE.Mesh(shapeGeometry('box', kUnit), this.material),
      new THREE.Mesh(shapeGeometry('cylinder', kUnit), this.material)];
    this.p = new THREE.Vector3();
    this.q = new THREE.Quaternion();
    this.s = new THREE.Vector3();
    this.hits = [];
  }

  // list: [{ name, shape: 'box'|'cylinder', size: [x, y, z], colour: THREE.Color }]
  build(list) {
    this.dispose();
    const n = list.length;
    this.count = n;
    this.names = list.map((b) => b.name);
    this.shapes = new Uint8Array(n);
    this.scales = new Float32Array(3 * n);
    this.positions = new Float64Array(3 * n);
    if (n === 0) return;
    list.forEach((b, i) => {
      this.shapes[i] = b.shape === 'cylinder' ? 1 : 0;
      this.scales.set([b.size[0], b.size[1], b.size[2]], 3 * i);
    });
    const units = this.probes.map((m) => m.geometry);
    let vertices = 0, indices = 0;
    for (let i = 0; i < n; ++i) {
      vertices += units[this.shapes[i]].attributes.position.count;
      indices += units[this.shapes[i]].index.count;
    }
    const position = new Float32Array(3 * vertices);
    const normal = new Float32Array(3 * vertices);
    const color = new Float32Array(3 * vertices);
    const body = new Float32Array(vertices);
    const index = vertices > 65535 ? new Uint32Array(indices) : new Uint16Array(indices);
    let v = 0, k = 0;
    for (let i = 0; i < n; ++i) {
      const unit = units[this.shapes[i]];
      const up = unit.attributes.position.array, un = unit.attributes.normal.array;
      const [sx, sy, sz] = this.scales.subarray(3 * i, 3 * i + 3);
      const c = list[i].colour;
      const count = unit.attributes.position.count;
      for (let j = 0; j < count; ++j) {
        const a = 3 * (v + j), b = 3 * j;
        // the unit shape at the body's size; its normals by the inverse scale (exact for
        // boxes and cylinders along x, and for any shape)
        position[a] = up[b] * sx;
        position[a + 1] = up[b + 1] * sy;
        position[a + 2] = up[b + 2] * sz;
        const nx = un[b] / sx, ny = un[b + 1] / sy, nz = un[b + 2] / sz;
        const l = Math.hypot(nx, ny, nz) || 1;
        normal[a] = nx / l;
        normal[a + 1] = ny / l;
        normal[a + 2] = nz / l;
        color[a] = c.r;
        color[a + 1] = c.g;
        color[a + 2] = c.b;
        body[v + j] = i;
      }
      const ui = unit.index.array;
      for (let j = 0; j < ui.length; ++j) index[k + j] = ui[j] + v;
      v += count;
      k += ui.length;
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(position, 3));
    geometry.setAttribute('normal', new THREE.BufferAttribute(normal, 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(color, 3));
    geometry.setAttribute('body', new THREE.BufferAttribute(body, 1));
    geometry.setIndex(new THREE.BufferAttribute(index, 1));

    // the poses: until the first frame, every body at the origin, unturned
    const rows = Math.ceil(n / kPerRow);
    this.poses = new Float32Array(8 * kPerRow * rows);
    for (let i = 0; i < kPerRow * rows; ++i) this.poses[8 * i + 7] = 1;
    this.texture = new THREE.DataTexture(this.poses, 2 * kPerRow, rows, THREE.RGBAFormat, THREE.FloatType);
    this.texture.magFilter = THREE.NearestFilter;
    this.texture.minFilter = THREE.NearestFilter;
    this.texture.generateMipmaps = false;
    this.texture.needsUpdate = true;
    this.uniforms.bodyPoses.value = this.texture;

    const mesh = new THREE.Mesh(geometry, this.material);
    // the vertices move in the shader: no bounding volume of the mesh is right for culling
    mesh.frustumCulled = false;
    mesh.name = 'bodies';
    this.parent.add(mesh);
    this.meshes = [mesh];
  }

  // poses: x y z qw qx qy qz per body, from `offset` (in numbers); a null (a value JSON cannot
  // hold: the simulation diverged) keeps the body where it was
  setPoses(poses, offset = 0) {
    const { poses: d, positions } = this;
    if (this.count === 0) return;
    for (let i = 0; i < this.count; ++i) {
      const k = offset + 7 * i;
      if (poses[k] === null || poses[k + 3] === null) continue;
      d[8 * i] = positions[3 * i] = poses[k];
      d[8 * i + 1] = positions[3 * i + 1] = poses[k + 1];
      d[8 * i + 2] = positions[3 * i + 2] = poses[k + 2];
      d[8 * i + 4] = poses[k + 4];
      d[8 * i + 5] = poses[k + 5];
      d[8 * i + 6] = poses[k + 6];
      d[8 * i + 7] = poses[k + 3];
    }
    this.texture.needsUpdate = true;
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

  // the nearest hit of a raycaster among the bodies (as drawn: the last poses): { body (index),
  // distance, point } or null
  pick(raycaster) {
    if (this.count === 0 || !this.meshes[0].visible) return null;
    const { p, q, s, hits, poses: d } = this;
    let best = null;
    for (let i = 0; i < this.count; ++i) {
      const probe = this.probes[this.shapes[i]];
      p.set(d[8 * i], d[8 * i + 1], d[8 * i + 2]);
      q.set(d[8 * i + 4], d[8 * i + 5], d[8 * i + 6], d[8 * i + 7]);
      s.set(this.scales[3 * i], this.scales[3 * i + 1], this.scales[3 * i + 2]);
      probe.matrixWorld.compose(p, q, s);
      hits.length = 0;
      probe.raycast(raycaster, hits);
      for (const h of hits) {
        if (!best || h.distance < best.distance) best = { body: i, distance: h.distance, point: h.point };
      }
    }
    return best;
  }

  dispose() {
    for (const mesh of this.meshes) {
      this.parent.remove(mesh);
      mesh.geometry.dispose();
    }
    if (this.texture) this.texture.dispose();
    this.texture = null;
    this.meshes = [];
    this.count = 0;
  }
}
