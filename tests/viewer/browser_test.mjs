// End to end in a real browser: `gaitlab run scripts/walk.lua --view` serves the page, Debian's
// headless chromium (driven by playwright-core from viewer/web/node_modules) opens it, and the
// test checks what a student would: the page loads, the robot moves on screen, pause stops
// time, step and reset work, a slider changes the parameter inside the engine (the run folder's
// events.csv says so, origin "viewer"), a bad value is refused with its range, and the run
// replays bit for bit. Screenshots go to OUT/ (docs/viewer.md shows them).
//
// Usage: node browser_test.mjs GAITLAB SOURCE_DIR OUT_DIR
// Exit 77 (ctest: skipped) only when no chromium is installed.
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { checker, findChromium, freshDir, launchChromium, loadPlaywright, serve, sleep, testArgs } from './browser_lib.mjs';

const [gaitlab, source, out] = testArgs('browser_test.mjs');
const chromium = findChromium();
const playwright = loadPlaywright(source);
freshDir(out);
const run = path.join(out, 'run');
const { check, finish } = checker();

// gaitlab, and the address it prints
const served = await serve(gaitlab, ['run', path.join(source, 'tests/viewer/scripts/walk.lua'), '--view',
  '--record', run, '--no-progress', '--', '120'], 'viewer');
const { child, url } = served;
console.log(`gaitlab serves ${url}`);

const browser = await launchChromium(playwright, chromium);
try {
  const page = await browser.newPage({ viewport: { width: 1200, height: 720 }, acceptDownloads: true });
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') pageErrors.push(m.text()); });
  const started = Date.now();
  await page.goto(url, { timeout: 90000 });
  await page.waitForFunction(() => window.gaitlab && window.gaitlab.drawn > 5, null, { timeout: 60000 });
  check(true, `the page loads and draws frames (${Date.now() - started} ms)`);
  const scene = await page.evaluate(() => window.gaitlab.scene);
  check(scene.bodies.length === 7 && scene.robots[0].name === 'snake' && scene.sensors[0].name === 'snake.imu6',
    'the scene has the snake\'s 7 bodies and its IMU');
  check(scene.objects.some((o) => o.kind === 'mesh' && o.name.startsWith('ramp')) &&
    scene.objects.filter((o) => o.name.startsWith('stairs')).length === 3 &&
    scene.objects.some((o) => o.dynamic === 0), 'the scene has the ramp, 3 steps and the movable box');

  // the robot moves on screen
  const pixels = () => page.evaluate(() => {
    const c = document.getElementById('scene');
    const s = document.createElement('canvas');
    s.width = 240; s.height = Math.round(240 * c.height / c.width);
    const g = s.getContext('2d');
    g.drawImage(c, 0, 0, s.width, s.height);
    return Array.from(g.getImageData(0, 0, s.width, s.height).data);
  });
  const poses = () => page.evaluate(() => window.gaitlab.frame.poses.slice());
  const time = () => page.evaluate(() => window.gaitlab.frame.time);
  await sleep(400);
  const p1 = await poses();
  const img1 = await pixels();
  await page.screenshot({ path: path.join(out, 'viewer-1.png') });
  await sleep(1000);
  const p2 = await poses();
  const img2 = await pixels();
  await page.screenshot({ path: path.join(out, 'viewer-2.png') });
  let moved = 0;
  for (let i = 0; i < 7 * 7; ++i) moved = Math.max(moved, Math.abs(p1[i] - p2[i]));
  check(moved > 0.005, `the bodies moved between two frames (${moved.toFixed(4)} m)`);
  let differ = 0;
  const colours = new Set();
  for (let i = 0; i < img1.length; i += 4) {
    if (Math.abs(img1[i] - img2[i]) + Math.abs(img1[i + 1] - img2[i + 1]) + Math.abs(img1[i + 2] - img2[i + 2]) > 30) differ++;
    colours.add((img1[i] >> 4) * 256 + (img1[i + 1] >> 4) * 16 + (img1[i + 2] >> 4));
  }
  check(differ > 20, `the picture changed between the two times (${differ} pixels)`);
  check(colours.size > 20, `the picture is not blank (${colours.size} colours)`);
  // the robot's orange is on screen
  let orange = 0;
  for (let i = 0; i < img2.length; i += 4) {
    if (img2[i] > 150 && img2[i + 1] > 60 && img2[i + 1] < 150 && img2[i + 2] < 80) orange++;
  }
  check(orange > 30, `the robot is drawn (${orange} orange pixels)`);

  // a live plot: the centre of mass by default, and a joint angle of the controller by its box
  await page.click('#add-plot');
  await page.waitForFunction(() => window.gaitlab.plots.length === 1 && window.gaitlab.plots[0].u);
  await page.locator('#plot-1 summary', { hasText: 'controller sine' }).click();
  await page.locator('#plot-1 input[data-series="sine.angle[1]"]').check();
  await page.waitForFunction(() => {
    const p = window.gaitlab.plots[0];
    return p.names.size === 2 && p.points() > 30 && p.u.data[2].filter((v) => v !== null).length > 30;
  }, null, { timeout: 15000 });
  const plotted = await page.evaluate(() => {
    const p = window.gaitlab.plots[0];
    const angles = p.u.data[2].filter((v) => v !== null);
    const c = p.u.ctx.canvas;
    const d = p.u.ctx.getImageData(0, 0, c.width, c.height).data;
    let ink = 0;
    for (let i = 0; i < d.length; i += 4) if (d[i + 3] > 0 && (d[i] < 200 || d[i + 2] < 200)) ink++;
    return { names: [...p.names], points: p.points(), min: Math.min(...angles), max: Math.max(...angles), ink };
  });
  check(plotted.names.includes('snake.com.x') && plotted.names.includes('sine.angle[1]'),
    `the plot shows ${plotted.names.join(' and ')}`);
  check(plotted.points > 30 && plotted.max - plotted.min > 20,
    `the plot has data: ${plotted.points} samples, sine.angle[1] from ${plotted.min.toFixed(1)} to ${plotted.max.toFixed(1)} deg`);
  check(plotted.ink > 500, `the plot is drawn (${plotted.ink} pixels of ink)`);
  // its live buffers' settings: samples every 10 ticks
  await page.fill('#live-every', '10');
  await page.locator('#live-every').dispatchEvent('change');
  await page.waitForFunction(() => {
    const t = window.gaitlab.plots[0].u.data[0];
    return t.length > 3 && Math.abs(t[t.length - 1] - t[t.length - 2] - 0.01) < 1e-9;
  }, null, { timeout: 10000 });
  check(true, 'the sampling rate is set from the page (one sample every 10 ticks)');
  await page.locator('#plot-1 summary', { hasText: 'series' }).click();  // fold the checkboxes

  // the live plot's exports: paused, so the CSV holds exactly what is drawn
  const downloaded = async (click) => {
    const [d] = await Promise.all([page.waitForEvent('download', { timeout: 15000 }), click()]);
    const file = path.join(out, d.suggestedFilename());
    await d.saveAs(file);
    return { file, name: d.suggestedFilename(), bytes: fs.readFileSync(file) };
  };
  await page.click('#plot-1 header button:has-text("Pause")');
  await sleep(300);
  const shown = await page.evaluate(() => window.gaitlab.plots[0].u.data.map((c) => c.slice()));
  const csv = await downloaded(() => page.click('#plot-1 .export-csv'));
  const lines = csv.bytes.toString('utf8').trimEnd().split('\n');
  check(/^simulation1-plot1-t[0-9.]+\.csv$/.test(csv.name) && lines[0] === 'time,snake.com.x,sine.angle[1]',
    `the live plot's CSV (${csv.name}) has the plotted series' columns (${lines[0]})`);
  const rows = lines.slice(1).map((l) => l.split(',').map((f) => (f === '' ? null : Number(f))));
  check(rows.length === shown[0].length && rows.length > 30 &&
    rows.every((r, i) => r.length === 3 && r.every((v, k) => v === shown[k][i])),
    `the CSV has the plot's ${shown[0].length} samples, row by row, exactly as plotted (${rows.length} rows)`);
  const png = await downloaded(() => page.click('#plot-1 .export-png'));
  const isPng = png.bytes.length > 8 && png.bytes.subarray(0, 8).equals(Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]));
  const pic = isPng ? await page.evaluate(async (b64) => {
    const bm = await createImageBitmap(await (await fetch(`data:image/png;base64,${b64}`)).blob());
    const c = new OffscreenCanvas(bm.width, bm.height);
    const g = c.getContext('2d');
    g.drawImage(bm, 0, 0);
    const d = g.getImageData(0, 0, bm.width, bm.height).data;
    const colours = new Set();
    let ink = 0;
    for (let i = 0; i < d.length; i += 4) {
      colours.add((d[i] >> 4) * 256 + (d[i + 1] >> 4) * 16 + (d[i + 2] >> 4));
      if (d[i] < 200 || d[i + 1] < 200 || d[i + 2] < 200) ink++;
    }
    return { width: bm.width, height: bm.height, colours: colours.size, ink };
  }, png.bytes.toString('base64')) : { colours: 0, ink: 0 };
  check(isPng && /\.png$/.test(png.name) && pic.width > 300 && pic.colours > 8 && pic.ink > 1000,
    `the live plot's PNG (${png.name}, ${pic.width}x${pic.height}) is a picture: ${pic.colours} colours, ${pic.ink} pixels of ink`);
  fs.copyFileSync(png.file, path.join(out, 'viewer-live-plot.png'));
  await page.click('#plot-1 header button:has-text("Play")');
  // a plot with no series has nothing to export: a message, no download
  await page.click('#add-plot');
  await page.waitForFunction(() => window.gaitlab.plots.length === 2);
  await page.evaluate(() => {
    const p = window.gaitlab.plots[1];
    p.names.clear();
    p.rebuild();
  });
  let empty = null;
  page.once('download', (d) => { empty = d.suggestedFilename(); });
  await page.click('#plot-2 .export-csv');
  await page.click('#plot-2 .export-png');
  await page.waitForFunction(() => window.gaitlab.messages.filter((m) => /plot 2: nothing to export yet \(choose a series first\)/.test(m.text)).length === 2);
  await sleep(300);
  check(empty === null, `an empty plot's exports say "nothing to export yet" and download nothing (${empty})`);
  await page.click('#plot-2 header button:has-text("×")');
  await page.screenshot({ path: path.join(out, 'viewer-plot.png') });

  // pause stops time
  await page.click('#play');
  await page.waitForFunction(() => window.gaitlab.frame.state.playing === false);
  await sleep(300);
  const t1 = await time();
  await sleep(700);
  const t2 = await time();
  check(t1 === t2, `pause stops time (t = ${t1} then ${t2})`);
  // a step: one control period
  // (frames are published while the step runs, so wait for its end, then check it stays there)
  await page.click('#step');
  await page.waitForFunction((t) => window.gaitlab.frame.time >= t + 0.03 - 1e-9, t2, { timeout: 30000 });
  await sleep(500);
  const t3 = await time();
  check(Math.abs(t3 - t2 - 0.03) < 1e-9, `step advances one control period (${t2} -> ${t3})`);

  // a slider sets the amplitude inside the engine
  await page.locator('#param-sine-amplitude').fill('20');
  await page.waitForFunction(() => window.gaitlab.frame.params[0] === 20, null, { timeout: 5000 });
  check(true, 'the amplitude slider set sine.amplitude = 20 (the engine reports it back)');
  // an out-of-range value is refused with the range, and changes nothing (the browser logs
  // the 400 as an error: the page's own errors are those before it)
  const errorsBefore = pageErrors.length;
  const refused = await page.evaluate(async () => {
    const r = await fetch('api/command' + location.search, {
      method: 'POST', headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify({ command: 'param', controller: 'sine', name: 'amplitude', value: 120 }),
    });
    return { status: r.status, body: await r.json() };
  });
  check(refused.status === 400 && /sine\.amplitude must be in \[0, 90\] deg \(got 120\)/.test(refused.body.error),
    `an out-of-range value is refused with its range (${refused.status}: ${refused.body.error})`);

  // a sensor switched off from the page
  await page.locator('input[data-sensor="snake.imu6"]').uncheck();
  await page.waitForFunction(() => window.gaitlab.frame.state.sensors[0] === false);
  check(true, 'the IMU is switched off from the page (the engine reports it back)');

  // play again
  await page.click('#play');
  await page.waitForFunction((t) => window.gaitlab.frame.time > t + 0.2, t3);
  check(true, 'play goes on after pause');
  await page.screenshot({ path: path.join(out, 'viewer-3.png') });

  // as fast as possible: the script ends (120 s simulated); the page still serves and plays on.
  // Under the sanitizers, beside the crowd test's 40 snakes, that took over 60 s once
  await page.selectOption('#speed', 'max');
  await page.waitForFunction(() => window.gaitlab.frame.state.finished === true, null, { timeout: 150000 });
  const tEnd = await time();
  check(Math.abs(tEnd - 120) < 1e-9, `the script's run ends at its 120 s (t = ${tEnd})`);
  check(/the script has finished/.test(served.err), 'gaitlab says the script has finished and still serves');
  await page.click('#reset');
  await page.waitForFunction(() => window.gaitlab.frame.time < 0.5);
  check(true, 'reset brings time back to 0');
  pageErrors.splice(errorsBefore, 1);
  check(pageErrors.length === 0, `no errors in the page (${pageErrors.join('; ')})`);
} finally {
  await browser.close();
}

// Ctrl-C quits; the run is closed as finished, and replays bit for bit
child.kill('SIGINT');
const end = await served.exited;
check(end.code === 0, `Ctrl-C after the script quits with status 0 (got ${end.code ?? end.signal})`);
check(/moved \d/.test(served.out), `the script printed its result (${served.out.trim()})`);
const events = fs.readFileSync(path.join(run, 'events.csv'), 'utf8');
check(/,viewer,param,sine\.amplitude,20,/.test(events), 'events.csv records sine.amplitude = 20 from the viewer');
check(/,viewer,reset,/.test(events), 'events.csv records the reset from the viewer');
check(/,viewer,sensor,snake\.imu6,0,/.test(events), 'events.csv records the IMU switched off from the viewer');
const runJson = JSON.parse(fs.readFileSync(path.join(run, 'run.json'), 'utf8'));
check(runJson.status === 'finished', `the run is closed as finished (${runJson.status})`);
const replay = spawnSync(gaitlab, ['replay', run], { encoding: 'utf8' });
check(replay.status === 0 && /^replay identical/.test(replay.stdout),
  `gaitlab replay reproduces the session bit for bit (${(replay.stdout + replay.stderr).trim()})`);

finish();
