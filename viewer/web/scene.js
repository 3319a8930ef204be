// The live 3D view of the viewer's page (docs/viewer.md): z up, as gaitlab's frames are. The
// scene message builds it; each frame moves the bodies (robots' bodies as one mesh posed in its
// vertex shader by bodies.js, moving objects as meshes); the camera orbits, pans, zooms and follows the first
// robot; a click on a body or object names it; the drawing resolution adapts to keep 30 frames
// per second (resolution.js) unless pinned. app.js owns the page around it.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { Bodies, shapeGeometry } from './bodies.js';
import { AdaptiveResolution, DrawingRate } from './resolution.js';

const robotColours = [0xe07b24, 0x2a7fbf, 0x3f9e4d, 0x9b4fb3];

// The floor's grid, computed per pixel from the world position (no texture: sampling a texture
// repeated 200 times at grazing angles cost more than everything else put together in software
// WebGL): a strong line each metre, a light one each 10 cm, their width kept at least a pixel,
// and where lines crowd closer than a few pixels, their mean colour instead of moiré. Colours
// are sRGB, as the lit floor looked.
function gridMaterial() {
  return new THREE.ShaderMaterial({
    uniforms: {
      base: { value: [237 / 255, 239 / 255, 241 / 255] },
      minor: { value: [190 / 255, 197 / 255, 206 / 255] },
      major: { value: [123 / 255, 133 / 255, 149 / 255] },
    },
    vertexShader: `
      varying vec2 vXY;
      void main() {
        vec4 w = modelMatrix * vec4(position, 1.0);
        vXY = w.xy;
        gl_Position = projectionMatrix * viewMatrix * w;
      }`,
    fragmentShader: `
      uniform vec3 base;
      uniform vec3 minor;
      uniform vec3 major;
      varying vec2 vXY;
      // how much of this pixel lines cover: c the position in cells, w cells per pixel and r
      // its inverse, h half a line's width in cells. Every operation counts where a CPU runs
      // this for each pixel (SwiftShader): one reciprocal per pixel, and edges and the fading
      // into the mean as straight ramps (clamp) rather than smoothstep, which look the same
      float lines(vec2 c, vec2 w, vec2 r, float h) {
        vec2 d = abs(fract(c + 0.5) - 0.5);        // to the nearest line, in cells
        // at least a pixel wide, then fainter (h / max(h, w / 2)), with an edge a pixel wide
        vec2 a = clamp((max(vec2(h), 0.5 * w) + 0.5 * w - d) * r, 0.0, 1.0) * min(2.0 * h * r, 1.0);
        // lines closer than a few pixels: their mean instead of moire
        a = mix(a, vec2(2.0 * h), clamp(w * (1.0 / 0.3) - (0.2 / 0.3), 0.0, 1.0));
        return 1.0 - (1.0 - a.x) * (1.0 - a.y);
      }
      void main() {
        vec2 w = fwidth(vXY);                      // metres per pixel
        vec2 r = 1.0 / max(w, 1e-6);               // pixels per metre (finite seen edge-on)
        vec3 c = mix(base, minor, lines(vXY * 10.0, w * 10.0, r * 0.1, 0.02));   // 4 mm every 10 cm
        gl_FragColor = vec4(mix(c, major, lines(vXY, w, r, 0.004)), 1.0);       // 8 mm every metre
      }`,
  });
}

function setPose(object, p, k = 0) {
  if (p[k] === null || p[k + 3] === null) return;   // a value JSON cannot hold (diverged)
  object.position.set(p[k], p[k + 1], p[k + 2]);
  object.quaternion.set(p[k + 4], p[k + 5], p[k + 6], p[k + 3]);
}

// gaitlab: the page's window.gaitlab (scene, frame, drawn); follow: the "Follow the robot" box
export function createView(gaitlab, canvas, { follow, status }) {
  // no antialiasing: edges are smoothed by drawing at the screen's full pixel ratio, and
  // multisampling costs about as much as the rest of the drawing without a GPU
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true,
    powerPreference: 'high-performance' });
  const adaptive = new AdaptiveResolution(renderer);
  renderer.setPixelRatio(adaptive.pixelRatio());
  const world = new THREE.Scene();
  world.background = new THREE.Color(0xdfe6ee);
  const camera = new THREE.PerspectiveCamera(45, 1, 0.005, 500);
  camera.up.set(0, 0, 1);
  camera.position.set(-0.6, -1.1, 0.7);
  const controls = new OrbitControls(camera, canvas);
  controls.target.set(0.3, 0, 0);
  controls.enableDamping = true;
  controls.update();

  // Lambert shading (diffuse light only): a fraction of the physically based material's cost
  // per pixel, and the same look for matte modules and floors
  world.add(new THREE.HemisphereLight(0xffffff, 0x8d8d8d, 2.2));
  const sun = new THREE.DirectionalLight(0xffffff, 2.0);
  sun.position.set(2, -3, 5);
  world.add(sun);
  const bodyMaterial = new THREE.MeshLambertMaterial({ color: 0xffffff });
  const objectMaterial = new THREE.MeshLambertMaterial({ color: 0x8e98a6 });
  const meshMaterial = new THREE.MeshLambertMaterial({ color: 0x8e98a6, side: THREE.DoubleSide });
  const dynamicMaterial = new THREE.MeshLambertMaterial({ color: 0xb59b6a });
  let floorMaterial = null;

  let dirty = true;                // something changed since the view was drawn last
  const invalidate = () => { dirty = true; };
  controls.addEventListener('change', invalidate);

  let group = new THREE.Group();   // what one scene message builds, but the robots' bodies
  world.add(group);
  const bodies = new Bodies(world, bodyMaterial);
  let dynamic = [];                // moving objects' meshes, in frame order
  let objects = [];                // every world object's mesh (for picking)
  let robots = [];

  function build(scene) {
    dirty = true;
    world.remove(group);
    group.traverse((o) => { if (o.geometry) o.geometry.dispose(); });
    group = new THREE.Group();
    world.add(group);
    robots = scene.robots;
    dynamic = [];
    objects = [];

    if (scene.floor.enabled) {
      // the grid is drawn by the floor's material (lines drawn as lines vanish on some GPUs)
      if (!floorMaterial) floorMaterial = gridMaterial();
      const floor = new THREE.Mesh(new THREE.PlaneGeometry(200, 200), floorMaterial);
      floor.name = 'floor';
      group.add(floor);
    }
    group.add(new THREE.AxesHelper(0.1));

    bodies.build(scene.bodies.map((b, i) => {
      const robotBody = i - scene.robots[b.robot].first_body;
      const colour = new THREE.Color(robotColours[b.robot % robotColours.length]);
      // alternate shades make the modules countable
      if (robotBody % 2) colour.multiplyScalar(0.8);
      return { name: b.name, shape: b.shape, size: b.size, colour };
    }));
    for (const o of scene.objects) {
      let mesh;
      if (o.kind === 'mesh') {
        const g = new THREE.BufferGeometry();
        g.setAttribute('position', new THREE.Float32BufferAttribute(o.positions, 3));
        g.computeVertexNormals();
        mesh = new THREE.Mesh(g, meshMaterial);
      } else {
        mesh = new THREE.Mesh(shapeGeometry(o.kind, o.size), o.dynamic >= 0 ? dynamicMaterial : objectMaterial);
        setPose(mesh, o.pose);
      }
      mesh.name = o.name;
      group.add(mesh);
      objects.push(mesh);
      if (o.dynamic >= 0) dynamic[o.dynamic] = mesh;
    }
  }

  // the centre of robot r's bodies into out, or null
  const centre = new THREE.Vector3();
  const lastCentre = new THREE.Vector3();
  const v = new THREE.Vector3();
  let haveCentre = false;
  function robotCentre(r, out) {
    const robot = robots[r];
    if (!robot || robot.bodies === 0) return null;
    out.set(0, 0, 0);
    for (let i = 0; i < robot.bodies; ++i) out.add(bodies.position(robot.first_body + i, v));
    return out.divideScalar(robot.bodies);
  }

  function viewAll() {
    const box = new THREE.Box3();
    bodies.expandBox(box);
    for (const m of dynamic) box.expandByObject(m);
    if (box.isEmpty()) box.set(new THREE.Vector3(-0.5, -0.5, 0), new THREE.Vector3(0.5, 0.5, 0.2));
    const c = box.getCenter(new THREE.Vector3());
    const size = Math.max(box.getSize(new THREE.Vector3()).length(), 0.3);
    controls.target.copy(c);
    camera.position.copy(c).add(new THREE.Vector3(-0.55, -1, 0.65).multiplyScalar(size));
    controls.update();
    dirty = true;
  }

  // the canvas's size on the page, kept by a ResizeObserver: reading clientWidth at every frame
  // would make the browser lay out the page right then whenever anything on it changed
  let cssWidth = canvas.clientWidth, cssHeight = canvas.clientHeight;
  // (it is called after the page's layout, where reading them costs nothing)
  new ResizeObserver(() => {
    cssWidth = canvas.clientWidth;
    cssHeight = canvas.clientHeight;
  }).observe(canvas);

  function resize() {
    const w = cssWidth, h = cssHeight;
    const ratio = adaptive.pixelRatio();
    if (renderer.getPixelRatio() !== ratio) {
      renderer.setPixelRatio(ratio);
      dirty = true;
    }
    if (canvas.width !== Math.floor(w * ratio) || canvas.height !== Math.floor(h * ratio)) {
      renderer.setSize(w, h, false);
      camera.aspect = w / Math.max(h, 1);
      camera.updateProjectionMatrix();
      dirty = true;
    }
  }

  let needsViewAll = false;
  let drawnFrame = null;
  let shown = '';
  // the latest frame's poses into the scene (and the camera after the robot); false when there
  // is no new frame of this scene
  function applyFrame() {
    const f = gaitlab.frame;
    if (f && f !== drawnFrame && gaitlab.scene && f.simulation === gaitlab.scene.simulation &&
        f.poses.length === (bodies.count + dynamic.length) * 7) {
      drawnFrame = f;
      bodies.setPoses(f.poses);
      for (let i = 0; i < dynamic.length; ++i) setPose(dynamic[i], f.poses, (bodies.count + i) * 7);
      if (needsViewAll) {
        needsViewAll = false;
        viewAll();
      }
      const c = robotCentre(0, centre);
      if (follow.checked && c && haveCentre) {
        // the camera keeps its place relative to the robot
        v.copy(c).sub(lastCentre);
        controls.target.add(v);
        camera.position.add(v);
      }
      haveCentre = c !== null;
      if (c) lastCentre.copy(c);
      gaitlab.drawn++;
      gaitlab.drawnTime = f.time;
      return true;
    }
    return false;
  }

  function drawNow() {
    renderer.render(world, camera);
    dirty = false;
    gaitlab.drawings++;
  }

  // draws the view now, whatever changed
  function render() {
    resize();
    applyFrame();
    controls.update();
    drawNow();
  }

  // At every animation frame the view is drawn only when something changed: a new frame, the
  // camera (a drag, its damping, following the robot), the size or resolution, a new scene,
  // or whatever calls invalidate() (the contact points). A paused simulation under a still
  // camera costs nothing; the canvas keeps its last drawing (preserveDrawingBuffer), so
  // screenshots and recordings read it as shown.
  // The simulation comes first: while it runs slower than its speed asks, the view is drawn at
  // most 36 times a second (DrawingRate, resolution.js).
  let shownFps = null;
  let shownScale = null;
  let shownYield = false;
  let drewLast = false;
  const rate = new DrawingRate();
  function draw(now) {
    requestAnimationFrame(draw);
    // the time since the last animation frame was drawing time only if that frame drew
    if (drewLast) adaptive.frame(now); else adaptive.idle(now);
    const behind = DrawingRate.behind(gaitlab.frame && gaitlab.frame.state);
    if (!rate.allow(now, behind, adaptive.pinned)) {
      drewLast = false;   // this frame is left to the simulation
    } else {
      resize();
      const fresh = applyFrame();
      controls.update();   // dispatches 'change' (invalidate) when the camera moved
      drewLast = dirty || fresh;
      if (drewLast) {
        drawNow();
        rate.drew();
      }
    }
    const yielding = rate.yielding;
    // the line under "Full quality", rewritten only when what it says changes
    if (status && adaptive.fps !== null &&
        (adaptive.fps !== shownFps || adaptive.scale !== shownScale || yielding !== shownYield)) {
      shownFps = adaptive.fps;
      shownScale = adaptive.scale;
      shownYield = yielding;
      const text = `drawing ${adaptive.fps.toFixed(0)} frames/s at ` +
        `${Math.round(adaptive.scale * 100)} % resolution` +
        `${adaptive.pinned ? ' (full quality)' : ''}` +
        `${yielding ? `, at most ${rate.rate} a second while the simulation is behind` : ''}`;
      if (text !== shown) status.textContent = shown = text;
    }
  }

  // a click (not a drag) on a body or an object: its name
  const raycaster = new THREE.Raycaster();
  const pointer = new THREE.Vector2();
  let down = null;
  function pick(clientX, clientY) {
    const r = canvas.getBoundingClientRect();
    pointer.set(((clientX - r.left) / r.width) * 2 - 1, -((clientY - r.top) / r.height) * 2 + 1);
    raycaster.setFromCamera(pointer, camera);
    const body = bodies.pick(raycaster);
    const hit = raycaster.intersectObjects(objects, false)[0];
    if (body && (!hit || body.distance <= hit.distance)) {
      const b = gaitlab.scene.bodies[body.body];
      return { kind: 'body', name: b.name, robot: robots[b.robot].name, index: body.body,
        point: body.point.toArray() };
    }
    if (hit) return { kind: 'object', name: hit.object.name, point: hit.point.toArray() };
    return null;
  }
  canvas.addEventListener('pointerdown', (e) => { down = { x: e.clientX, y: e.clientY }; });
  canvas.addEventListener('pointerup', (e) => {
    if (!down || Math.hypot(e.clientX - down.x, e.clientY - down.y) > 4) return;
    down = null;
    gaitlab.picked = pick(e.clientX, e.clientY);
    if (view.onpick) view.onpick(gaitlab.picked);
  });

  const view = {
    THREE, world, camera, controls, renderer, adaptive, bodies,
    build,
    viewAll,
    viewAllSoon() { needsViewAll = true; },
    pick,
    // full size until the function returned is called: screenshots and recordings
    pin() {
      const release = adaptive.pin();
      resize();
      return release;
    },
    // draws now (at the resolution in force), e.g. right before reading the canvas
    render,
    // draws again at the next animation frame (after a change to the scene made elsewhere)
    invalidate,
    onpick: null,
  };
  requestAnimationFrame(draw);
  return view;
}
