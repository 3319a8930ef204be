// The viewer's frame rate in the browser: `gaitlab run bench/lua/crowd.lua --view` with N
// snakes (8 modules each, at real time), Debian's headless chromium (software WebGL,
// SwiftShader) on the page through playwright-core, and for 10 s: how often the page paints
// (requestAnimationFrame callbacks per second), how many new simulation frames it draws per
// second (window.gaitlab.drawn) and receives (window.gaitlab.frames). Prints a markdown table
// (docs/performance.md §9).
//
// With RUNS=K each count is measured K times (the counts interleaved) and the medians printed;
// the last column is the drawing resolution the page settled on (its adaptive resolution,
// docs/viewer.md; "-" for a page without it) at the end of the last run.
//
// DRAW_COST=1 measures instead how long one drawing of the view at its full size takes (the
// page's own renderer, waited for), which depends less on what else the machine runs.
//
// Usage: [VIEWPORT=WxH] [RUNS=K] [FULL_QUALITY=1] [DRAW_COST=1] node bench/viewer_fps.mjs GAITLAB SOURCE_DIR [ROBOTS...]
// (default 1 10 40 80 robots, a 1200x720 page, one run)
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import fs from 'node:fs';
import path from 'node:path';

const [gaitlab, source, ...counts] = process.argv.slice(2);
if (!gaitlab || !source) {
  console.error('usage: node bench/viewer_fps.mjs GAITLAB SOURCE_DIR [ROBOTS...]');
  process.exit(2);
}
const robots = counts.length ? counts.map(Number) : [1, 10, 40, 80];
const chromium = process.env.CHROMIUM || '/usr/bin/chromium';
if (!fs.existsSync(chromium)) {
  console.error(`no chromium at ${chromium} (apt-get install chromium; tools/setup.sh does)`);
  process.exit(1);
}
const require = createRequire(path.resolve(source, 'viewer/web/package.json'));
const playwright = require('playwright-core');
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const seconds = 10;
// the page's size (VIEWPORT=WxH, default 1200x720): software WebGL's cost grows with its pixels
const [width, height] = (process.env.VIEWPORT || '1200x720').split('x').map(Number);

async function measure(n) {
  const child = spawn(gaitlab, ['run', path.join(source, 'bench/lua/crowd.lua'), '--view',
    '--no-record', '--no-progress', '--', String(n), '8', '600'],
  { stdio: ['ignore', 'ignore', 'pipe'] });
  let stderr = '';
  child.stderr.on('data', (d) => { stderr += d; });
  try {
    let url = null;
    for (let i = 0; i < 300 && !url; ++i) {
      const m = stderr.match(/viewer: (http:\/\/\S+)/);
      if (m) url = m[1];
      else await sleep(100);
    }
    if (!url) throw new Error(`gaitlab printed no address:\n${stderr}`);
    const browser = await playwright.chromium.launch({
      executablePath: chromium,
      args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
        '--ignore-gpu-blocklist'],
    });
    try {
      const page = await browser.newPage({ viewport: { width, height } });
      await page.goto(url, { timeout: 120000 });
      await page.waitForFunction((k) => window.gaitlab.scene &&
        window.gaitlab.scene.bodies.length >= k && window.gaitlab.drawn > 10, n * 8,
      { timeout: 120000 });
      if (process.env.DRAW_COST === '1') {
        // the time of one drawing of the view at its full size, waited for (a one-pixel
        // read-back): the median of 15, after 3 to warm up
        const ms = await page.evaluate(() => {
          const { renderer, world, camera } = window.gaitlab.three;
          const release = window.gaitlab.three.pin ? window.gaitlab.three.pin() : () => {};
          const gl = renderer.getContext();
          const px = new Uint8Array(4);
          const times = [];
          for (let i = 0; i < 18; ++i) {
            const t0 = performance.now();
            renderer.render(world, camera);
            gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
            if (i >= 3) times.push(performance.now() - t0);
          }
          release();
          times.sort((x, y) => x - y);
          return times[Math.floor(times.length / 2)];
        });
        return { drawMs: ms, bodies: await page.evaluate(() => window.gaitlab.scene.bodies.length) };
      }
      // FULL_QUALITY=1: the page's "Full quality" box ticked (no adaptive resolution)
      if (process.env.FULL_QUALITY === '1') await page.check('#full-quality');
      await page.evaluate(() => {
        window.paints = 0;
        const count = () => { window.paints++; requestAnimationFrame(count); };
        requestAnimationFrame(count);
      });
      await sleep(1000);
      const read = () => page.evaluate(() => ({ paints: window.paints,
        drawn: window.gaitlab.drawn, frames: window.gaitlab.frames,
        time: window.gaitlab.frame.time, wall: performance.now() / 1000 }));
      const a = await read();
      await sleep(seconds * 1000);
      const b = await read();
      const wall = b.wall - a.wall;
      const scale = await page.evaluate(() => {
        const t = window.gaitlab.three;
        return t && t.adaptive ? t.adaptive.scale : null;
      });
      return { scale, bodies: (await page.evaluate(() => window.gaitlab.scene.bodies.length)),
        paints: (b.paints - a.paints) / wall, drawn: (b.drawn - a.drawn) / wall,
        frames: (b.frames - a.frames) / wall, rate: (b.time - a.time) / wall };
    } finally {
      await browser.close();
    }
  } finally {
    child.kill('SIGINT');
  }
}

const runs = Number(process.env.RUNS || 1);
const results = new Map(robots.map((n) => [n, []]));
for (let k = 0; k < runs; ++k) {
  for (const n of robots) results.get(n).push(await measure(n));
}
const median = (list, key) => {
  const v = list.map((r) => r[key]).sort((a, b) => a - b);
  return v.length % 2 ? v[(v.length - 1) / 2] : (v[v.length / 2 - 1] + v[v.length / 2]) / 2;
};
console.log(`page ${width}x${height}, ${runs === 1 ? 'one run' : `median of ${runs} runs`}`);
if (process.env.DRAW_COST === '1') {
  console.log('| robots | bodies | ms per full-size drawing |');
  console.log('|---|---|---|');
  for (const n of robots) {
    const list = results.get(n);
    console.log(`| ${n} | ${list[0].bodies} | ${median(list, 'drawMs').toFixed(1)} |`);
  }
  process.exit(0);
}
console.log('| robots | bodies | paints / s | new frames drawn / s | frames received / s | simulated s per wall s | resolution |');
console.log('|---|---|---|---|---|---|---|');
for (const n of robots) {
  const list = results.get(n);
  const last = list[list.length - 1];
  console.log(`| ${n} | ${last.bodies} | ${median(list, 'paints').toFixed(1)} | ` +
    `${median(list, 'drawn').toFixed(1)} | ${median(list, 'frames').toFixed(1)} | ` +
    `${median(list, 'rate').toFixed(2)} | ${last.scale === null ? '-' : `${Math.round(last.scale * 100)} %`} |`);
}
