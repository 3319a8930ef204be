// Where the drawing time of the viewer's page goes (docs/performance.md §9): one page of
// `gaitlab run bench/lua/crowd.lua --view` (N snakes of 8 modules) in Debian's headless
// chromium (software WebGL, SwiftShader), its resolution held fixed, and parts of it switched
// off in turn, each for a few seconds, round after round (so every part sees the same machine
// load). For each: drawings per second and the CPU time per drawing of chromium's GPU process
// (WebGL in SwiftShader, compositing the page) and of its renderer (JavaScript, style, layout).
// CPU time per drawing depends far less on what else the machine runs than frame rates do.
//
// Parts (PARTS=name:scale,...; scale: the resolution, one of the adaptive steps):
//   full      everything, as the page draws it
//   nofloor   without the floor
//   nobodies  without the robots' bodies
//   empty     nothing in the 3D scene (the background colour only)
//   ...nodom  (suffix) the panel, the plots and the overlay hidden: the 3D view alone on the page
//   ...-ID    (suffix) the page's element with that id hidden (e.g. full-overlay, full-panel,
//             full-plots-section, full-params-section)
// PAUSED=1: the simulation paused (the view still drawn at every animation frame, the page's
// texts unchanged).
//
// Chromium composites the page in software (--disable-gpu-compositing), as in
// bench/viewer_fps.mjs; CHROMIUM_ARGS='SWITCHES' puts other switches in its place (separated by
// spaces; "-" for none: the page composited by SwiftShader too).
// WEB=DIR: the page's own files (index.html, *.js, style.css) served from DIR instead of those
// built into gaitlab (as in bench/viewer_fps.mjs).
//
// Usage: [PARTS=...] [CHROMIUM_ARGS=...] [ROUNDS=2] [SECONDS=6] [PAUSED=1] [WEB=DIR] node bench/viewer_parts.mjs GAITLAB SOURCE_DIR [ROBOTS]
import fs from 'node:fs';
import { chromiumProcesses, cpuSeconds, findChromium, launchBrowser, loadPlaywright, servePageFrom,
  sleep, startCrowd } from './viewer_lib.mjs';

const [gaitlab, source, robots = '40'] = process.argv.slice(2);
if (!gaitlab || !source || !/^[1-9]\d*$/.test(robots)) {
  console.error('usage: node bench/viewer_parts.mjs GAITLAB SOURCE_DIR [ROBOTS]');
  process.exit(2);
}
const chromium = findChromium();
const scales = [1, 0.8, 0.64, 0.5, 0.4, 0.32, 0.25];
const parts = (process.env.PARTS || 'full:1,full:0.5,full:0.25,nofloor:0.5,nobodies:0.5,empty:0.5,fullnodom:0.5,emptynodom:0.5')
  .split(',').map((p) => {
    const [what, scale] = p.split(':');
    if (!/^(full|nofloor|nobodies|empty)(nodom|-[a-z][a-z0-9-]*)?$/.test(what) || !scales.includes(Number(scale))) {
      console.error(`PARTS: ${p} is not PART:SCALE (PART full, nofloor, nobodies, empty, each with or ` +
        `without the suffix nodom or -ID; SCALE one of ${scales.join(', ')})`);
      process.exit(2);
    }
    return { name: p, what, scale: Number(scale) };
  });
const rounds = Number(process.env.ROUNDS || 2);
const seconds = Number(process.env.SECONDS || 6);
const playwright = loadPlaywright(source);
const chromiumArgs = process.env.CHROMIUM_ARGS || '--disable-gpu-compositing';
const { child, url } = await startCrowd(gaitlab, source, robots);
const browser = await launchBrowser(playwright, chromium, chromiumArgs);
try {
  const page = await browser.newPage({ viewport: { width: 1200, height: 720 } });
  if (process.env.WEB) await servePageFrom(page, process.env.WEB);
  await page.goto(url, { timeout: 120000 });
  await page.waitForFunction(() => window.gaitlab.scene && window.gaitlab.drawn > 10, null, { timeout: 120000 });
  if (process.env.PAUSED === '1') {
    await page.click('#play');
    await page.waitForFunction(() => window.gaitlab.frame.state.playing === false);
  }
  await page.evaluate((steps) => {
    const g = window.gaitlab;
    const t = g.three;
    // every animation frame draws (a page that draws only what changed: invalidated each time)
    window.drawings = 0;
    const count = () => {
      window.drawings++;
      if (t.invalidate) t.invalidate();
      requestAnimationFrame(count);
    };
    requestAnimationFrame(count);
    t.adaptive.frame = () => false;   // the resolution stays where it is put
    if (t.adaptive.idle) t.adaptive.idle = () => {};
    g.showPart = (what, scale) => {
      t.adaptive.level = steps.indexOf(scale);
      t.world.traverse((o) => { o.visible = true; });
      if (what.startsWith('nofloor')) t.world.traverse((o) => { if (o.name === 'floor') o.visible = false; });
      if (what.startsWith('nobodies')) for (const m of t.bodies.meshes) m.visible = false;
      if (what.startsWith('empty')) t.world.traverse((o) => { if (o !== t.world) o.visible = false; });
      for (const id of ['panel', 'plots-section', 'overlay']) {
        document.getElementById(id).style.display = what.endsWith('nodom') ? 'none' : '';
      }
      for (const el of document.querySelectorAll('[data-hidden-part]')) {
        el.style.display = '';
        delete el.dataset.hiddenPart;
      }
      const dash = what.indexOf('-');
      if (dash > 0) {
        const el = document.getElementById(what.slice(dash + 1));
        if (!el) throw new Error(`no element with the id ${what.slice(dash + 1)} on the page`);
        el.style.display = 'none';
        el.dataset.hiddenPart = '1';
      }
    };
  }, scales);
  const procs = chromiumProcesses(process.pid, child.pid);
  const sum = (list) => list.reduce((s, p) => s + cpuSeconds(p) * 1000, 0);
  const results = new Map(parts.map((p) => [p.name, []]));
  for (let r = 0; r < rounds; ++r) {
    for (const part of parts) {
      await page.evaluate(([w, s]) => window.gaitlab.showPart(w, s), [part.what, part.scale]);
      await sleep(1500);
      const a = { n: await page.evaluate(() => window.drawings), gpu: sum(procs.gpu), ren: sum(procs.renderer), t: Date.now() };
      const load = fs.readFileSync('/proc/loadavg', 'utf8').split(' ')[0];
      await sleep(seconds * 1000);
      const b = { n: await page.evaluate(() => window.drawings), gpu: sum(procs.gpu), ren: sum(procs.renderer), t: Date.now() };
      const n = Math.max(b.n - a.n, 1);
      results.get(part.name).push({ fps: n / ((b.t - a.t) / 1000), gpu: (b.gpu - a.gpu) / n, ren: (b.ren - a.ren) / n, load });
    }
  }
  console.log(`${robots} robots, page 1200x720${process.env.WEB ? ` (page from ${process.env.WEB})` : ''}, chromium ${chromiumArgs === '-' ? 'with no extra switches' : chromiumArgs}, ${rounds} rounds of ${seconds} s per part` +
    `${process.env.PAUSED === '1' ? ', simulation paused' : ''}`);
  console.log('| part | resolution | drawings / s | GPU process CPU ms per drawing | renderer CPU ms per drawing | load |');
  console.log('|---|---|---|---|---|---|');
  for (const part of parts) {
    const list = results.get(part.name);
    const all = (k, d) => list.map((x) => x[k].toFixed(d)).join(', ');
    console.log(`| ${part.what} | ${Math.round(part.scale * 100)} % | ${all('fps', 1)} | ${all('gpu', 1)} | ${all('ren', 1)} | ${list.map((x) => x.load).join(', ')} |`);
  }
} finally {
  await browser.close();
  child.kill('SIGINT');
}
