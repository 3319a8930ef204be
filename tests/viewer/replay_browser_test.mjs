// A recorded run in a real browser: `gaitlab run scripts/walk.lua` records two runs, `gaitlab
// view RUN` serves the first, Debian's headless chromium (driven by playwright-core) opens it,
// and the test checks what a student would: the run loads with its scene, scrubbing the
// timeline moves the drawn bodies (the pictures differ), a recorded plot shows the data, its
// CSV download matches data.csv, its PNG and the 3D view's screenshot are pictures that are
// not blank, a WebM recording of the view is a WebM, and the picker opens the other run.
// Screenshots go to OUT/ (docs/viewer.md shows them).
//
// Usage: node replay_browser_test.mjs GAITLAB SOURCE_DIR OUT_DIR
// Exit 77 (ctest: skipped) only when no chromium is installed.
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { checker, findChromium, freshDir, launchChromium, loadPlaywright, serve, sleep, testArgs } from './browser_lib.mjs';
import { webmInfo } from './webm.mjs';

const [gaitlab, source, out] = testArgs('replay_browser_test.mjs');
const chromium = findChromium();
const playwright = loadPlaywright(source);
freshDir(out);
const { check, finish } = checker();

// two recorded runs side by side
const walk = path.join(source, 'tests/viewer/scripts/walk.lua');
for (const [name, seconds] of [['walk', '3'], ['short', '1']]) {
  const r = spawnSync(gaitlab, ['run', walk, '--record', path.join(out, name), '--', seconds],
    { encoding: 'utf8' });
  if (r.status !== 0) {
    console.error(`FAIL: gaitlab run failed: ${r.stderr}`);
    process.exit(1);
  }
}
const run = path.join(out, 'walk');

const served = await serve(gaitlab, ['view', run], 'viewer', { cwd: out });
const { child, url } = served;
console.log(`gaitlab serves ${url}`);

// data.csv's columns as written: the strings, not numbers read back
function columns(file, names) {
  const lines = fs.readFileSync(file, 'utf8').trimEnd().split('\n');
  const header = lines[0].split(',');
  const at = ['time', ...names].map((n) => header.indexOf(n));
  return [['time', ...names].join(','),
    ...lines.slice(1).map((l) => { const f = l.split(','); return at.map((i) => f[i]).join(','); })];
}

const browser = await launchChromium(playwright, chromium);
try {
  const page = await browser.newPage({ viewport: { width: 1000, height: 660 }, acceptDownloads: true });
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') pageErrors.push(m.text()); });
  // a PNG (bytes) as the page decodes it: its size and how many colours it has
  const picture = (bytes) => page.evaluate(async (b64) => {
    const blob = await (await fetch(`data:image/png;base64,${b64}`)).blob();
    const bm = await createImageBitmap(blob);
    const c = new OffscreenCanvas(bm.width, bm.height);
    const g = c.getContext('2d');
    g.drawImage(bm, 0, 0);
    const d = g.getImageData(0, 0, bm.width, bm.height).data;
    const colours = new Set();
    for (let i = 0; i < d.length; i += 4) colours.add((d[i] >> 4) * 256 + (d[i + 1] >> 4) * 16 + (d[i + 2] >> 4));
    return { width: bm.width, height: bm.height, colours: colours.size };
  }, bytes.toString('base64'));
  const isPng = (b) => b.length > 8 && b.subarray(0, 8).equals(Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]));
  const downloaded = async (click) => {
    const [d] = await Promise.all([page.waitForEvent('download', { timeout: 15000 }), click()]);
    const file = path.join(out, d.suggestedFilename());
    await d.saveAs(file);
    return { file, name: d.suggestedFilename(), bytes: fs.readFileSync(file) };
  };

  const started = Date.now();
  await page.goto(url, { timeout: 90000 });
  await page.waitForFunction(() => window.gaitlab && window.gaitlab.replay && window.gaitlab.replay.info &&
    window.gaitlab.drawn > 0, null, { timeout: 60000 });
  check(true, `the recorded run loads and is drawn (${Date.now() - started} ms)`);
  const info = await page.evaluate(() => window.gaitlab.replay.info);
  const scene = await page.evaluate(() => window.gaitlab.scene);
  check(info.name === 'walk' && info.poses && info.scene_rebuilt,
    `the page has the run ${info.name}, its poses and its rebuilt scene`);
  check(scene.bodies.length === 7 && scene.objects.some((o) => o.name.startsWith('ramp')),
    'the scene has the snake\'s 7 bodies and the ramp');

  // scrub: the drawn bodies move
  const pixels = () => page.evaluate(() => {
    const c = document.getElementById('scene');
    const s = document.createElement('canvas');
    s.width = 240; s.height = Math.round(240 * c.height / c.width);
    const g = s.getContext('2d');
    g.drawImage(c, 0, 0, s.width, s.height);
    return Array.from(g.getImageData(0, 0, s.width, s.height).data);
  });
  await page.uncheck('#follow');  // the camera stays: only the robot moves in the picture
  const scrub = async (t) => {
    await page.$eval('#timeline', (el, v) => {
      el.value = v;
      el.dispatchEvent(new Event('input'));
      el.dispatchEvent(new Event('change'));
    }, t);
    // drawn, not only received: the canvas then shows it (a loaded machine can take long)
    await page.waitForFunction((v) => Math.abs(window.gaitlab.frame.time - v) < 1e-9 &&
      window.gaitlab.drawnTime !== null && Math.abs(window.gaitlab.drawnTime - v) < 1e-9, t,
    { timeout: 30000 });
  };
  await scrub(0);
  const p0 = await page.evaluate(() => window.gaitlab.frame.poses.slice());
  const img0 = await pixels();
  await scrub(2.4);
  const p1 = await page.evaluate(() => window.gaitlab.frame.poses.slice());
  const img1 = await pixels();
  let moved = 0;
  for (let i = 0; i < 7 * 7; ++i) moved = Math.max(moved, Math.abs(p0[i] - p1[i]));
  check(moved > 0.01, `scrubbing to 2.4 s moves the bodies (${moved.toFixed(4)} m)`);
  let differ = 0;
  for (let i = 0; i < img0.length; i += 4) {
    if (Math.abs(img0[i] - img1[i]) + Math.abs(img0[i + 1] - img1[i + 1]) + Math.abs(img0[i + 2] - img1[i + 2]) > 30) differ++;
  }
  check(differ > 20, `the pictures at 0 s and 2.4 s differ (${differ} pixels)`);
  const label = await page.textContent('#timeline-time');
  check(/^2\.400 \/ [23]\.\d{3} s$/.test(label), `the timeline says where it is (${label})`);

  // play: time goes on to the end, and stops there
  await scrub(2.5);
  await page.click('#play');
  await page.waitForFunction(() => window.gaitlab.frame.state.playing === false &&
    window.gaitlab.frame.time === window.gaitlab.replay.info.end, null, { timeout: 10000 });
  check(true, 'play plays the run to its end and stops');

  // a recorded plot: the centre of mass, and a joint's angle by its box
  await page.click('#add-recorded-plot');
  await page.waitForFunction(() => window.gaitlab.replay.plots.length === 1 && window.gaitlab.replay.plots[0].u);
  await page.locator('#recorded-plot-1 summary', { hasText: 'robot snake' }).click();
  await page.locator('#recorded-plot-1 input[data-series="snake.angle[3]"]').check();
  await page.waitForFunction(() => {
    const p = window.gaitlab.replay.plots[0];
    return p.names.length === 2 && p.u && p.u.data.length === 3;
  }, null, { timeout: 10000 });
  const plotted = await page.evaluate(() => {
    const p = window.gaitlab.replay.plots[0];
    const angles = p.u.data[2];
    const c = p.u.ctx.canvas;
    const d = p.u.ctx.getImageData(0, 0, c.width, c.height).data;
    let ink = 0;
    for (let i = 0; i < d.length; i += 4) if (d[i + 3] > 0 && (d[i] < 200 || d[i + 2] < 200)) ink++;
    return { names: p.names, points: p.points(), min: Math.min(...angles), max: Math.max(...angles), ink };
  });
  check(plotted.points === info.rows && plotted.max - plotted.min > 10,
    `the plot has every row (${plotted.points} of ${info.rows}), snake.angle[3] from ${plotted.min.toFixed(1)} to ${plotted.max.toFixed(1)} deg`);
  check(plotted.ink > 500, `the plot is drawn (${plotted.ink} pixels of ink)`);
  await page.locator('#recorded-plot-1 summary', { hasText: 'series' }).click();  // fold
  await scrub(1.2);
  await page.screenshot({ path: path.join(out, 'viewer-recorded.png') });

  // its CSV: data.csv's columns, exactly
  const csv = await downloaded(() => page.click('#recorded-plot-1 .export-csv'));
  const expected = columns(path.join(run, 'data.csv'), ['snake.com.x', 'snake.angle[3]']);
  const got = csv.bytes.toString('utf8').trimEnd().split('\n');
  check(csv.name === 'walk.csv' && got.length === expected.length && got.every((l, i) => l === expected[i]),
    `the CSV download (${csv.name}, ${got.length} lines) is data.csv's time, snake.com.x and snake.angle[3]`);
  // its PNG
  const png = await downloaded(() => page.click('#recorded-plot-1 .export-png'));
  const pp = isPng(png.bytes) ? await picture(png.bytes) : { colours: 0 };
  check(isPng(png.bytes) && pp.colours > 8 && pp.width > 300,
    `the plot's PNG (${png.name}, ${pp.width}x${pp.height}) is a picture with ${pp.colours} colours`);
  fs.copyFileSync(png.file, path.join(out, 'viewer-recorded-plot.png'));

  // a screenshot of the 3D view
  const shot = await downloaded(() => page.click('#screenshot'));
  const sp = isPng(shot.bytes) ? await picture(shot.bytes) : { colours: 0 };
  check(isPng(shot.bytes) && sp.colours > 20,
    `the screenshot (${shot.name}, ${sp.width}x${sp.height}) is not blank (${sp.colours} colours)`);

  // a WebM recording of the view while it plays
  await scrub(0);
  await page.click('#record-video');
  await page.click('#play');
  await sleep(1000);
  const video = await downloaded(() => page.click('#record-video'));
  const vi = webmInfo(video.bytes);
  check(vi.ok && video.bytes.length > 5000,
    `the recorded video (${video.name}, ${video.bytes.length} bytes) is a WebM with ${vi.blocks} frames over ${vi.seconds.toFixed(2)} s ${vi.error}`);

  // bad requests from the page: a folder the picker does not offer, a seek that is no time
  const refused = await page.evaluate(async () => {
    const r = await fetch('api/run/open', { method: 'POST', headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify({ path: '/etc' }) });
    return { status: r.status, body: await r.json() };
  });
  check(refused.status === 400 && /not a run folder the list offers/.test(refused.body.error),
    `opening /etc is refused (${refused.status}: ${refused.body.error})`);

  // the picker opens the other run
  const options = await page.$$eval('#run-picker option', (os) => os.map((o) => o.value));
  const other = options.find((o) => o.endsWith('short'));
  check(other !== undefined, `the picker offers the other run (${options.join(', ')})`);
  await page.selectOption('#run-picker', other);
  await page.click('#run-open');
  await page.waitForFunction(() => window.gaitlab.replay.info.name === 'short' &&
    window.gaitlab.frame.state.recorded.end < 1.01, null, { timeout: 30000 });
  check(true, 'the picker opens the other run: its name and its 1 s timeline');
  // the refused open, which the browser logs as a failed resource
  const logged = pageErrors.findIndex((e) => /status of 400/.test(e));
  if (logged >= 0) pageErrors.splice(logged, 1);
  check(pageErrors.length === 0, `no errors in the page (${pageErrors.join('; ')})`);
} finally {
  await browser.close();
}

child.kill('SIGINT');
const end = await served.exited;
check(end.code === 130 || end.code === 0, `Ctrl-C quits gaitlab view (status ${end.code ?? end.signal})`);
const runJson = JSON.parse(fs.readFileSync(path.join(run, 'run.json'), 'utf8'));
check(runJson.status === 'finished', 'the run folder is as it was (finished)');

finish();
