// What the floor's grid costs to draw in software WebGL (docs/performance.md §9): one page of
// `gaitlab run bench/lua/crowd.lua --view` (N snakes, paused) in Debian's headless chromium
// (SwiftShader), its view at full resolution, drawn with the floor's fragment shader taken from
// each given copy of the page (the `fragmentShader` of scene.js's gridMaterial), and for
// reference with a flat floor (one colour) and without the floor. Finely interleaved in the
// same page (10 drawings of each in turn, 12 rounds), so every shader sees the same machine
// load; each drawing is waited for (a one-pixel read-back). Prints the median and the 10th
// percentile of the ms per drawing.
//
// Usage: node bench/viewer_floor.mjs GAITLAB SOURCE_DIR ROBOTS WEB_DIR [WEB_DIR...]
//   e.g. node bench/viewer_floor.mjs build/gaitlab . 40 main-copy/viewer/web viewer/web
import fs from 'node:fs';
import path from 'node:path';
import { findChromium, launchBrowser, loadPlaywright, startCrowd } from './viewer_lib.mjs';

const [gaitlab, source, robots, ...webs] = process.argv.slice(2);
if (!gaitlab || !source || !/^[1-9]\d*$/.test(robots || '') || webs.length === 0) {
  console.error('usage: node bench/viewer_floor.mjs GAITLAB SOURCE_DIR ROBOTS WEB_DIR [WEB_DIR...]');
  process.exit(2);
}
const chromium = findChromium();
// the floor's fragment shader in a copy of the page
function floorShader(dir) {
  const file = path.join(dir, 'scene.js');
  if (!fs.existsSync(file)) {
    console.error(`${dir}: no scene.js (a copy of viewer/web expected)`);
    process.exit(2);
  }
  const text = fs.readFileSync(file, 'utf8');
  const start = text.indexOf('function gridMaterial');
  const open = text.indexOf('fragmentShader: `', start);
  const close = text.indexOf('`', open + 'fragmentShader: `'.length);
  if (start < 0 || open < 0 || close < 0) {
    console.error(`${file}: no gridMaterial with a fragmentShader: \`...\` in it`);
    process.exit(2);
  }
  return text.slice(open + 'fragmentShader: `'.length, close);
}
const variants = webs.map((dir) => ({ name: dir, frag: floorShader(dir) }));
variants.push({ name: 'flat floor (one colour)',
  frag: 'uniform vec3 base;\nvoid main() { gl_FragColor = vec4(base, 1.0); }' });
variants.push({ name: 'no floor', frag: null });

const playwright = loadPlaywright(source);
const { child, url } = await startCrowd(gaitlab, source, robots);
const browser = await launchBrowser(playwright, chromium);
try {
  const page = await browser.newPage({ viewport: { width: 1200, height: 720 } });
  await page.goto(url, { timeout: 120000 });
  await page.waitForFunction((k) => window.gaitlab.scene && window.gaitlab.scene.bodies.length >= k &&
    window.gaitlab.drawn > 10, Number(robots) * 8, { timeout: 120000 });
  await page.click('#play');
  await page.waitForFunction(() => window.gaitlab.frame.state.playing === false);
  const load = fs.readFileSync('/proc/loadavg', 'utf8').split(' ')[0];
  const result = await page.evaluate((list) => {
    const t = window.gaitlab.three;
    const release = t.pin();
    const { renderer, world, camera, THREE } = t;
    let floor = null;
    world.traverse((o) => { if (o.name === 'floor') floor = o; });
    if (!floor) throw new Error('the scene has no floor');
    const own = floor.material;
    const materials = list.map((v) => (v.frag === null ? null : new THREE.ShaderMaterial({
      uniforms: own.uniforms, vertexShader: own.vertexShader, fragmentShader: v.frag })));
    const gl = renderer.getContext();
    const px = new Uint8Array(4);
    const use = (i) => {
      floor.visible = materials[i] !== null;
      if (materials[i]) floor.material = materials[i];
    };
    const draw = () => {
      renderer.render(world, camera);
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
    };
    // compile and warm up each
    for (let i = 0; i < list.length; ++i) {
      use(i);
      for (let k = 0; k < 3; ++k) draw();
    }
    const times = list.map(() => []);
    for (let round = 0; round < 12; ++round) {
      for (let i = 0; i < list.length; ++i) {
        use(i);
        for (let k = 0; k < 10; ++k) {
          const t0 = performance.now();
          draw();
          times[i].push(performance.now() - t0);
        }
      }
    }
    floor.material = own;
    floor.visible = true;
    release();
    return { width: gl.drawingBufferWidth, height: gl.drawingBufferHeight,
      times: times.map((l) => l.sort((a, b) => a - b)) };
  }, variants);
  console.log(`${robots} robots (paused), view ${result.width}x${result.height} (page 1200x720), ` +
    `load ${load} at the start; ms per drawing of the whole view`);
  console.log('| floor shader | median | 10th percentile |');
  console.log('|---|---|---|');
  variants.forEach((v, i) => {
    const l = result.times[i];
    const at = (q) => l[Math.floor(l.length * q)].toFixed(1);
    console.log(`| ${v.name} | ${at(0.5)} | ${at(0.1)} |`);
  });
} finally {
  await browser.close();
  child.kill('SIGINT');
}
