// The viewer's frame rate in the browser: `gaitlab run bench/lua/crowd.lua --view` with N
// snakes (8 modules each, at real time), Debian's headless chromium (software WebGL,
// SwiftShader) on the page through playwright-core, and for 10 s: how often the page draws its
// 3D view (window.gaitlab.drawings; a page that draws at every animation frame:
// requestAnimationFrame callbacks), how many new simulation frames it draws per
// second (window.gaitlab.drawn) and receives (window.gaitlab.frames). Prints a markdown table
// (docs/performance.md §9).
//
// Where the time goes, in the same 10 s: the CPU time (ms per wall second) of gaitlab (the
// simulation and its server), of chromium's renderer (the page's JavaScript, style, layout and
// its compositor), of chromium's GPU process (WebGL drawn by SwiftShader, and the compositing
// of the page) and of chromium's other processes, also per drawing of the view (steadier than
// frame rates on a loaded machine); the JavaScript time per drawing inside
// the page's requestAnimationFrame callbacks (the 3D view's update and its WebGL calls); and the
// load average of the machine when the window began.
//
// With RUNS=K each count is measured K times (the counts interleaved) and the medians printed;
// the resolution column is the drawing resolution the page settled on (its adaptive resolution,
// docs/viewer.md; "-" for a page without it) at the end of the last run.
//
// WEB=DIR[,DIR...]: the page's own files (index.html, *.js, style.css) served from each DIR in
// turn instead of those built into gaitlab (the libraries stay gaitlab's), interleaved with the
// counts: two versions of the page compared on the same machine at the same time, e.g. a
// `git archive main viewer/web` beside the working tree's viewer/web.
// Chromium runs with WebGL in SwiftShader (--use-angle=swiftshader --enable-unsafe-swiftshader
// --ignore-gpu-blocklist) and, by default, --disable-gpu-compositing: the page composited in
// software, as chromium does on a machine without a GPU (and as `gaitlab view RUN --video`
// runs it), rather than by SwiftShader too, which then reads every composited frame back
// (docs/performance.md §9).
// CHROMIUM_ARGS=SET[;SET...]: each set of switches in turn in place of --disable-gpu-compositing
// (switches separated by spaces, "-" for none), interleaved like WEB, e.g.
// CHROMIUM_ARGS='-;--disable-gpu-compositing' compares the two ways of compositing the page.
// PAUSED=1: the simulation paused during the 10 s (what a page costs while nothing moves).
// FULL_QUALITY=1: the page's "Full quality" box ticked (no adaptive resolution).
// PROFILE=1: chromium's JavaScript profiler runs over the 10 s; the functions with the most
// time of their own are printed after the table.
//
// DRAW_COST=1 measures instead how long one drawing of the view at its full size takes (the
// page's own renderer, waited for; the median of 40) and the CPU time chromium's GPU process
// spends per such drawing, which depend less on what else the machine runs.
//
// Usage: [VIEWPORT=WxH] [RUNS=K] [WEB=DIR,...] [PAUSED=1] [FULL_QUALITY=1] [PROFILE=1] [DRAW_COST=1]
//        node bench/viewer_fps.mjs GAITLAB SOURCE_DIR [ROBOTS...]
// (default 1 10 40 80 robots, a 1200x720 page, one run)
import fs from 'node:fs';
import path from 'node:path';
import { chromiumProcesses, cpuSeconds as cpu, findChromium, launchBrowser, loadPlaywright,
  servePageFrom, sleep, startCrowd } from './viewer_lib.mjs';

const [gaitlab, source, ...counts] = process.argv.slice(2);
if (!gaitlab || !source) {
  console.error('usage: node bench/viewer_fps.mjs GAITLAB SOURCE_DIR [ROBOTS...]');
  process.exit(2);
}
const robots = counts.length ? counts.map(Number) : [1, 10, 40, 80];
if (robots.some((n) => !Number.isInteger(n) || n < 1)) {
  console.error(`ROBOTS must be whole numbers from 1 (got ${counts.join(' ')})`);
  process.exit(2);
}
const chromium = findChromium();
const webs = process.env.WEB ? process.env.WEB.split(',') : [null];
for (const w of webs) {
  if (w !== null && !fs.existsSync(path.join(w, 'index.html'))) {
    console.error(`WEB: ${w} has no index.html (a copy of viewer/web expected)`);
    process.exit(2);
  }
}
const argSets = process.env.CHROMIUM_ARGS ? process.env.CHROMIUM_ARGS.split(';').map((a) => a.trim())
  : ['--disable-gpu-compositing'];
const playwright = loadPlaywright(source);
const seconds = 10;
// the page's size (VIEWPORT=WxH, default 1200x720): software WebGL's cost grows with its pixels
const [width, height] = (process.env.VIEWPORT || '1200x720').split('x').map(Number);

async function measure(n, { web, args }) {
  const { child, url } = await startCrowd(gaitlab, source, n);
  try {
    const browser = await launchBrowser(playwright, chromium, args);
    try {
      const page = await browser.newPage({ viewport: { width, height } });
      if (web !== null) await servePageFrom(page, web);
      // the time of the page's animation-frame callbacks (JavaScript, WebGL calls issued)
      await page.addInitScript(() => {
        window.rafMs = 0;
        const raf = window.requestAnimationFrame.bind(window);
        window.requestAnimationFrame = (cb) => raf((t) => {
          const t0 = performance.now();
          try { cb(t); } finally { window.rafMs += performance.now() - t0; }
        });
      });
      await page.goto(url, { timeout: 120000 });
      await page.waitForFunction((k) => window.gaitlab.scene &&
        window.gaitlab.scene.bodies.length >= k && window.gaitlab.drawn > 10, n * 8,
      { timeout: 120000 });
      if (process.env.DRAW_COST === '1') {
        // the time of one drawing of the view at its full size, waited for (a one-pixel
        // read-back): the median of 40, after 5 to warm up; and the CPU time of chromium's GPU
        // process over those 40 (less moved by the machine's load than the wall time)
        const gpu = chromiumProcesses(process.pid, child.pid).gpu;
        const gpuCpu = () => gpu.reduce((s, p) => s + cpu(p), 0);
        await page.evaluate(() => {
          const { renderer, world, camera } = window.gaitlab.three;
          window.drawCostRelease = window.gaitlab.three.pin ? window.gaitlab.three.pin() : () => {};
          window.drawCost = (k) => {
            const gl = renderer.getContext();
            const px = new Uint8Array(4);
            const times = [];
            for (let i = 0; i < k; ++i) {
              const t0 = performance.now();
              renderer.render(world, camera);
              gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
              times.push(performance.now() - t0);
            }
            return times;
          };
          window.drawCost(5);
        });
        const c0 = gpuCpu();
        const times = await page.evaluate(() => window.drawCost(40));
        const gpuMs = ((gpuCpu() - c0) * 1000) / times.length;
        await page.evaluate(() => window.drawCostRelease());
        times.sort((x, y) => x - y);
        const ms = times[Math.floor(times.length / 2)];
        return { drawMs: ms, gpuMs, bodies: await page.evaluate(() => window.gaitlab.scene.bodies.length) };
      }
      if (process.env.FULL_QUALITY === '1') await page.check('#full-quality');
      if (process.env.PAUSED === '1') {
        await page.click('#play');
        await page.waitForFunction(() => window.gaitlab.frame.state.playing === false);
      }
      await page.evaluate(() => {
        window.paints = 0;
        const count = () => { window.paints++; requestAnimationFrame(count); };
        requestAnimationFrame(count);
      });
      await sleep(1000);
      let cdp = null;
      if (process.env.PROFILE === '1') {
        cdp = await page.context().newCDPSession(page);
        await cdp.send('Profiler.enable');
        await cdp.send('Profiler.setSamplingInterval', { interval: 500 });
        await cdp.send('Profiler.start');
      }
      const procs = chromiumProcesses(process.pid, child.pid);
      const cpus = () => ({ gaitlab: cpu(child.pid),
        renderer: procs.renderer.reduce((s, p) => s + cpu(p), 0),
        gpu: procs.gpu.reduce((s, p) => s + cpu(p), 0),
        other: procs.other.reduce((s, p) => s + cpu(p), 0) });
      const load = Number(fs.readFileSync('/proc/loadavg', 'utf8').split(' ')[0]);
      // drawings of the 3D view: the page counts them where it draws only what changed, else
      // every animation frame draws
      const read = () => page.evaluate(() => ({
        paints: window.gaitlab.drawings !== undefined ? window.gaitlab.drawings : window.paints,
        raf: window.rafMs,
        drawn: window.gaitlab.drawn, frames: window.gaitlab.frames,
        time: window.gaitlab.frame.time, wall: performance.now() / 1000 }));
      const a = await read();
      const ca = cpus();
      await sleep(seconds * 1000);
      const b = await read();
      const cb = cpus();
      const wall = b.wall - a.wall;
      let profile = null;
      if (cdp) profile = (await cdp.send('Profiler.stop')).profile;
      const scale = await page.evaluate(() => {
        const t = window.gaitlab.three;
        return t && t.adaptive ? t.adaptive.scale : null;
      });
      const per = (k) => ((cb[k] - ca[k]) * 1000) / wall;
      return { scale, bodies: (await page.evaluate(() => window.gaitlab.scene.bodies.length)),
        paints: (b.paints - a.paints) / wall, drawn: (b.drawn - a.drawn) / wall,
        frames: (b.frames - a.frames) / wall, rate: (b.time - a.time) / wall,
        rafMs: (b.raf - a.raf) / Math.max(b.paints - a.paints, 1),
        cpuGaitlab: per('gaitlab'), cpuRenderer: per('renderer'), cpuGpu: per('gpu'),
        cpuOther: per('other'), load, profile };
    } finally {
      await browser.close();
    }
  } finally {
    child.kill('SIGINT');
  }
}

// self time per function of a CDP profile, in ms: [[name, ms], ...] largest first
function selfTimes(profile) {
  const byId = new Map(profile.nodes.map((node) => [node.id, node]));
  const ms = new Map();
  for (let i = 0; i < profile.samples.length; ++i) {
    const node = byId.get(profile.samples[i]);
    const f = node.callFrame;
    const name = `${f.functionName || '(anonymous)'} ${f.url ? `${path.basename(f.url)}:${f.lineNumber + 1}` : ''}`.trim();
    ms.set(name, (ms.get(name) || 0) + (profile.timeDeltas[i] || 0) / 1000);
  }
  return [...ms].sort((x, y) => y[1] - x[1]);
}

const runs = Number(process.env.RUNS || 1);
// every page version with every set of chromium switches
const variants = webs.flatMap((web) => argSets.map((args) => ({ web, args })));
const key = (n, v) => `${n}|${v.web}|${v.args}`;
const results = new Map();
for (let k = 0; k < runs; ++k) {
  for (const n of robots) {
    for (const v of variants) {
      if (!results.has(key(n, v))) results.set(key(n, v), []);
      results.get(key(n, v)).push(await measure(n, v));
    }
  }
}
const median = (list, name) => {
  const v = list.map((r) => r[name]).sort((a, b) => a - b);
  return v.length % 2 ? v[(v.length - 1) / 2] : (v[v.length / 2 - 1] + v[v.length / 2]) / 2;
};
const label = (v) => `${v.web === null ? 'built in' : v.web}` +
  `${argSets.length > 1 ? ` (${v.args === '-' ? 'no extra switches' : v.args})` : ''}`;
console.log(`page ${width}x${height}, ${runs === 1 ? 'one run' : `median of ${runs} runs`}` +
  `${argSets.length === 1 ? `, chromium ${argSets[0] === '-' ? 'with no extra switches' : argSets[0]}`
    : ''}` +
  `${process.env.PAUSED === '1' ? ', simulation paused' : ''}` +
  `${process.env.FULL_QUALITY === '1' ? ', Full quality' : ''}`);
if (process.env.DRAW_COST === '1') {
  console.log('| page | robots | bodies | ms per full-size drawing | GPU process CPU ms per drawing |');
  console.log('|---|---|---|---|---|');
  for (const n of robots) {
    for (const v of variants) {
      const list = results.get(key(n, v));
      console.log(`| ${label(v)} | ${n} | ${list[0].bodies} | ${median(list, 'drawMs').toFixed(1)} | ` +
        `${median(list, 'gpuMs').toFixed(1)} |`);
    }
  }
  process.exit(0);
}
console.log('| page | robots | bodies | drawings / s | new frames drawn / s | frames received / s | ' +
  'simulated s per wall s | resolution | JS ms per drawing | CPU ms per drawing: renderer | ' +
  'GPU process | CPU ms/s: gaitlab | renderer | GPU process | chromium other | load |');
console.log('|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|');
for (const n of robots) {
  for (const v of variants) {
    const list = results.get(key(n, v));
    const last = list[list.length - 1];
    for (const r of list) {
      r.rendererPer = r.cpuRenderer / Math.max(r.paints, 0.1);
      r.gpuPer = r.cpuGpu / Math.max(r.paints, 0.1);
    }
    const m = (name, digits = 1) => median(list, name).toFixed(digits);
    console.log(`| ${label(v)} | ${n} | ${last.bodies} | ${m('paints')} | ${m('drawn')} | ${m('frames')} | ` +
      `${m('rate', 2)} | ${last.scale === null ? '-' : `${Math.round(last.scale * 100)} %`} | ` +
      `${m('rafMs')} | ${m('rendererPer')} | ${m('gpuPer')} | ${m('cpuGaitlab', 0)} | ` +
      `${m('cpuRenderer', 0)} | ${m('cpuGpu', 0)} | ${m('cpuOther', 0)} | ` +
      `${list.map((r) => r.load.toFixed(1)).join(', ')} |`);
  }
}
if (process.env.PROFILE === '1') {
  for (const n of robots) {
    for (const v of variants) {
      const list = results.get(key(n, v));
      console.log(`\n${label(v)}, ${n} robots: the page's JavaScript, ms of its own per 10 s (last run)`);
      for (const [name, ms] of selfTimes(list[list.length - 1].profile).slice(0, 25)) {
        console.log(`  ${ms.toFixed(0).padStart(6)}  ${name}`);
      }
    }
  }
}
