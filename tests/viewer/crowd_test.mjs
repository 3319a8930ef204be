// Many robots in the browser: `gaitlab run bench/lua/crowd.lua --view` with 40 snakes of 8
// modules (360 bodies) in Debian's headless chromium (software WebGL, far slower than a GPU).
// Checks what a student would see: every robot is drawn where the engine says it is, in its
// colour (the pixels at each robot's projected bodies), also after they moved (robots lifted in
// a frame made by the test, and after a while of playing); the drawing stays cheap (the 360
// bodies in one draw call; nothing drawn again while nothing moves, no slider label rewritten
// while its value stays); a click on a body names it; when frames are slow the view is
// drawn at a lower resolution, while a screenshot, "Full quality" and a recording are at the
// full size.
//
// Usage: node crowd_test.mjs GAITLAB SOURCE_DIR OUT_DIR
// Exit 77 (ctest: skipped) only when no chromium is installed.
import fs from 'node:fs';
import path from 'node:path';
import { checker, findChromium, freshDir, launchChromium, loadPlaywright, serve, sleep, testArgs } from './browser_lib.mjs';

const [gaitlab, source, out] = testArgs('crowd_test.mjs');
const chromium = findChromium();
const playwright = loadPlaywright(source);
freshDir(out);
const { check, finish } = checker();
const robots = 40;
const modules = 8;

const served = await serve(gaitlab, ['run', path.join(source, 'bench/lua/crowd.lua'), '--view',
  '--no-record', '--no-progress', '--', String(robots), String(modules), '600'], 'viewer');
console.log(`gaitlab serves ${served.url}`);

// the robots' colours (scene.js), as hue classes of a pixel: orange, blue, green, purple
const kinds = ['orange', 'blue', 'green', 'purple'];
function hueOf([r, g, b]) {
  const max = Math.max(r, g, b), min = Math.min(r, g, b);
  if (max - min < 40) return 'grey';   // the floor, the sky, the grid
  if (r === max && b === min && g < r - 40) return 'orange';
  if (b === max && r === min) return 'blue';
  if (g === max && b < g - 20 && r < g - 20) return 'green';
  if (r > g + 30 && b > g + 30) return 'purple';
  return 'other';
}

const browser = await launchChromium(playwright, chromium);
try {
  const page = await browser.newPage({ viewport: { width: 1200, height: 720 }, acceptDownloads: true });
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') pageErrors.push(m.text()); });
  await page.goto(served.url, { timeout: 90000 });
  await page.waitForFunction((n) => window.gaitlab.scene && window.gaitlab.scene.robots.length === n &&
    window.gaitlab.drawn > 5, robots, { timeout: 60000 });
  const bodies = await page.evaluate(() => window.gaitlab.scene.bodies.length);
  // the whole crowd in view, still: pause, no following
  await page.uncheck('#follow');
  await page.click('#play');
  await page.waitForFunction(() => window.gaitlab.frame.state.playing === false);
  await page.click('#home');
  await sleep(1500);

  // where each robot's bodies are on the page (the engine's poses through the page's camera),
  // and the colour of the canvas there (read back at the canvas's own resolution)
  const look = () => page.evaluate(() => {
    const g = window.gaitlab;
    const { THREE, camera, renderer } = g.three;
    g.three.render();
    const c = renderer.domElement;
    const s = document.createElement('canvas');
    s.width = c.clientWidth; s.height = c.clientHeight;
    const x2 = s.getContext('2d');
    x2.drawImage(c, 0, 0, s.width, s.height);
    const img = x2.getImageData(0, 0, s.width, s.height).data;
    const p = g.frame.poses;
    const v = new THREE.Vector3();
    const bodies = g.scene.bodies.map((b, i) => {
      v.set(p[7 * i], p[7 * i + 1], p[7 * i + 2]).project(camera);
      const x = Math.round((v.x + 1) / 2 * s.width), y = Math.round((1 - v.y) / 2 * s.height);
      const k = 4 * (y * s.width + x);
      const inside = x >= 0 && y >= 0 && x < s.width && y < s.height;
      return { robot: b.robot, name: b.name, x, y, inside, rgb: inside ? [img[k], img[k + 1], img[k + 2]] : null };
    });
    return { bodies, calls: renderer.info.render.calls, width: c.width, height: c.height,
      cssWidth: c.clientWidth, cssHeight: c.clientHeight, dpr: window.devicePixelRatio,
      scale: g.three.adaptive.scale };
  });
  const seen = await look();
  await page.screenshot({ path: path.join(out, 'crowd.png') });
  const inside = seen.bodies.filter((b) => b.inside).length;
  check(inside === bodies && bodies >= robots * modules, `every body projects inside the view (${inside} of ${bodies})`);
  // a robot is drawn where it is when most of its bodies' centres have its colour there
  let drawn = 0;
  const wrong = [];
  for (let r = 0; r < robots; ++r) {
    const mine = seen.bodies.filter((b) => b.robot === r && b.inside);
    const right = mine.filter((b) => hueOf(b.rgb) === kinds[r % 4]).length;
    if (right >= mine.length / 2) drawn++; else wrong.push(`${r}: ${right}/${mine.length}`);
  }
  check(drawn === robots, `all ${robots} robots are drawn in their colours where the engine puts them ` +
    `(${drawn}${wrong.length ? `; not: ${wrong.slice(0, 5).join(', ')}` : ''})`);
  // and nothing of theirs where there is no body: the sky above the crowd is grey
  const sky = await page.evaluate(() => {
    const c = window.gaitlab.three.renderer.domElement;
    const s = document.createElement('canvas');
    s.width = c.clientWidth; s.height = c.clientHeight;
    const x2 = s.getContext('2d');
    x2.drawImage(c, 0, 0, s.width, s.height);
    return Array.from(x2.getImageData(Math.round(s.width / 2), 2, 1, 1).data).slice(0, 3);
  });
  check(hueOf(sky) === 'grey', `the sky is not painted with robots (${sky})`);
  check(seen.calls > 0 && seen.calls <= 10, `${bodies} bodies take ${seen.calls} draw calls`);
  // the bodies are one mesh drawn with one call: hiding them takes exactly one draw call away
  const calls = await page.evaluate(() => {
    const { bodies, renderer } = window.gaitlab.three;
    const count = () => { window.gaitlab.three.render(); return renderer.info.render.calls; };
    const shown = count();
    for (const m of bodies.meshes) m.visible = false;
    const hidden = count();
    for (const m of bodies.meshes) m.visible = true;
    return { shown, hidden, again: count() };
  });
  check(calls.shown - calls.hidden === 1 && calls.again === calls.shown,
    `the ${bodies} bodies are drawn with one draw call (${calls.shown} with them, ${calls.hidden} without)`);

  // the bodies move with their poses and keep their colours: in a frame made here, robots 0 to
  // 3 (one of each colour) lifted 0.25 m; the pixels at their bodies' new places turn to their
  // colours, and every other robot stays where it was in its colour
  const lift = await page.evaluate(() => {
    const g = window.gaitlab;
    const { THREE, camera, renderer } = g.three;
    const c = renderer.domElement;
    const s = document.createElement('canvas');
    s.width = c.clientWidth; s.height = c.clientHeight;
    const x2 = s.getContext('2d');
    const picture = () => {
      g.three.render();
      x2.drawImage(c, 0, 0, s.width, s.height);
      return x2.getImageData(0, 0, s.width, s.height).data;
    };
    const original = g.frame;
    const lifted = original.poses.slice();
    g.scene.bodies.forEach((b, i) => { if (b.robot < 4) lifted[7 * i + 2] += 0.25; });
    const v = new THREE.Vector3();
    const at = (img, p, i) => {
      v.set(p[7 * i], p[7 * i + 1], p[7 * i + 2]).project(camera);
      const x = Math.round((v.x + 1) / 2 * s.width), y = Math.round((1 - v.y) / 2 * s.height);
      if (x < 0 || y < 0 || x >= s.width || y >= s.height) return null;
      const k = 4 * (y * s.width + x);
      return [img[k], img[k + 1], img[k + 2]];
    };
    const before = picture();
    g.frame = { ...original, poses: lifted };
    const after = picture();
    const list = g.scene.bodies.map((b, i) => ({ robot: b.robot, was: at(before, lifted, i),
      now: at(after, lifted, i) }));
    g.frame = original;
    g.three.render();
    return list;
  });
  const liftedRight = [];
  let liftedOk = true;
  for (let r = 0; r < 4; ++r) {
    const mine = lift.filter((b) => b.robot === r && b.now !== null);
    const turned = mine.filter((b) => hueOf(b.now) === kinds[r] && hueOf(b.was) !== kinds[r]).length;
    liftedRight.push(`${turned}/${mine.length}`);
    if (mine.length === 0 || turned < mine.length / 2) liftedOk = false;
  }
  check(liftedOk, `robots lifted in a frame are drawn where they went, in their colours (bodies whose pixel ` +
    `turned to the robot's colour: ${liftedRight.join(', ')})`);
  const stayed = lift.filter((b) => b.robot >= 4 && b.now !== null);
  const stayedRight = stayed.filter((b) => hueOf(b.now) === kinds[b.robot % 4]).length;
  check(stayedRight >= 0.8 * stayed.length,
    `the robots not lifted stay where they were in their colours (${stayedRight} of ${stayed.length} bodies)`);

  // a click on a body names it
  const target = seen.bodies.find((b, i) => b.robot === 13 && i === seen.bodies.findIndex((x) => x.robot === 13) + 3);
  const robotName = await page.evaluate((r) => window.gaitlab.scene.robots[r].name, target.robot);
  const box = await page.locator('#scene').boundingBox();
  await page.mouse.click(box.x + target.x, box.y + target.y);
  await page.waitForFunction(() => window.gaitlab.picked !== null, null, { timeout: 5000 }).catch(() => {});
  const picked = await page.evaluate(() => window.gaitlab.picked);
  // the pixel's neighbours may be another module of the same snake: the robot counts
  check(picked && picked.kind === 'body' && picked.robot === robotName,
    `a click on ${robotName}'s 4th body picks a body of ${robotName} (${picked ? `${picked.robot} ${picked.name}` : 'nothing'})`);
  const label = await page.textContent('#picked');
  check(picked && label.includes(`${picked.robot} ${picked.name}`), `the overlay names it (${label})`);
  await page.mouse.click(box.x + box.width / 2, box.y + 3);
  await page.waitForFunction(() => window.gaitlab.picked === null, null, { timeout: 5000 }).catch(() => {});
  check(await page.evaluate(() => window.gaitlab.picked === null), 'a click on the sky picks nothing');

  // nothing moves (paused, a still camera): the view is not drawn again, and what it shows stays;
  // a drag of the camera draws it again. The picture as the canvas keeps it, not redrawn here
  const picture = () => page.evaluate(() => {
    const c = window.gaitlab.three.renderer.domElement;
    const s = document.createElement('canvas');
    s.width = 160; s.height = 120;
    s.getContext('2d').drawImage(c, 0, 0, s.width, s.height);
    return Array.from(s.getContext('2d').getImageData(0, 0, s.width, s.height).data);
  });
  const differ = (a, b) => a.filter((x, i) => Math.abs(x - b[i]) > 8).length;
  await sleep(1000);   // the camera's damping after the clicks dies out
  // the renderer's drawings (three.js counts them) and the resolution
  const still = () => page.evaluate(() => ({ drawings: window.gaitlab.three.renderer.info.render.frame,
    scale: window.gaitlab.three.adaptive.scale }));
  const still0 = await still();
  const pic0 = await picture();
  await sleep(1500);
  const still1 = await still();
  const pic1 = await picture();
  check(still1.drawings === still0.drawings && still1.scale === still0.scale && differ(pic0, pic1) === 0,
    `paused under a still camera the view is not drawn again (${still1.drawings - still0.drawings} drawings in 1.5 s) ` +
    `and shows the same picture at the same resolution (${still1.scale})`);
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width / 2 + 120, box.y + box.height / 2 + 30, { steps: 6 });
  await page.mouse.up();
  await sleep(1000);
  const turned = (await still()).drawings;
  const pic2 = await picture();
  check(turned > still1.drawings && differ(pic1, pic2) > 1000,
    `a drag of the camera draws the view again (${turned - still1.drawings} drawings; ${differ(pic1, pic2) / 4 | 0} pixels changed)`);

  // playing: new frames are drawn; the sliders' labels (3 for each of the 40 robots) are not
  // written again while their values stay, the time is
  await page.click('#play');
  await page.waitForFunction(() => window.gaitlab.frame.state.playing === true);
  const mutations = await page.evaluate(() => new Promise((resolve) => {
    const counts = { params: 0, time: 0 };
    const watch = (id, key) => new MutationObserver((list) => { counts[key] += list.length; })
      .observe(document.getElementById(id), { subtree: true, childList: true, characterData: true, attributes: true });
    watch('params', 'params');
    watch('time', 'time');
    const drawn = window.gaitlab.drawn;
    setTimeout(() => resolve({ ...counts, drawn: window.gaitlab.drawn - drawn }), 2000);
  }));
  check(mutations.drawn > 0 && mutations.time > 0 && mutations.params === 0,
    `playing, ${mutations.drawn} new frames drawn in 2 s; the time written ${mutations.time} times, ` +
    `the unchanged sliders ${mutations.params} times`);
  // after a while of playing the robots are still drawn in their colours where the engine has
  // moved them
  await page.click('#play');
  await page.waitForFunction(() => window.gaitlab.frame.state.playing === false);
  await sleep(500);
  const later = await look();
  let moved = 0;
  later.bodies.forEach((b, i) => { if (Math.hypot(b.x - seen.bodies[i].x, b.y - seen.bodies[i].y) >= 1) moved++; });
  let drawnLater = 0;
  for (let r = 0; r < robots; ++r) {
    const mine = later.bodies.filter((b) => b.robot === r && b.inside);
    if (mine.filter((b) => hueOf(b.rgb) === kinds[r % 4]).length >= mine.length / 2) drawnLater++;
  }
  check(moved > 0 && drawnLater === robots, `after playing, ${moved} bodies moved on the page and all ` +
    `${robots} robots are drawn in their colours where the engine puts them (${drawnLater})`);
  await page.click('#play');
  await page.waitForFunction(() => window.gaitlab.frame.state.playing === true);

  // slow frames: the resolution goes down, the page keeps its size. Slow for sure: a budget
  // of 10 ms a frame, less than a 60 Hz screen gives (a fast machine draws this crowd at 30
  // frames per second even in software); and every step down counted as a gain (on a busy
  // machine fewer pixels may not make frames shorter, and then the page goes back up:
  // resolution_test.mjs checks that)
  await page.evaluate(() => {
    window.gaitlab.three.adaptive.budget = 10;
    window.gaitlab.three.adaptive.gain = Infinity;
  });
  // the canvas takes the lower resolution at the next drawing, which may come a few animation
  // frames later while the simulation is behind (the page then draws at most 36 times a second)
  await page.waitForFunction(() => {
    const { adaptive, renderer } = window.gaitlab.three;
    const c = renderer.domElement;
    return adaptive.scale < 1 && c.width < c.clientWidth * window.devicePixelRatio;
  }, null, { timeout: 30000 }).catch(() => {});
  const low = await page.evaluate(() => {
    const { adaptive, renderer } = window.gaitlab.three;
    const c = renderer.domElement;
    return { scale: adaptive.scale, width: c.width, css: c.clientWidth * window.devicePixelRatio,
      text: document.getElementById('drawing').textContent };
  });
  check(low.scale < 1 && low.width < low.css,
    `slow frames lower the drawing resolution (${low.scale}: ${low.width} of ${low.css} pixels wide; "${low.text}")`);

  // a screenshot is at the full size anyway
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#screenshot')]);
  const file = path.join(out, 'screenshot.png');
  await download.saveAs(file);
  const png = fs.readFileSync(file);
  const pw = png.readUInt32BE(16), ph = png.readUInt32BE(20);
  check(png.subarray(1, 4).toString() === 'PNG' && pw === Math.floor(seen.cssWidth * seen.dpr) &&
    ph === Math.floor(seen.cssHeight * seen.dpr),
    `the screenshot has the view's full size (${pw}x${ph} for ${seen.cssWidth}x${seen.cssHeight} at ${seen.dpr})`);

  // "Full quality": the full size, and it stays
  await page.check('#full-quality');
  await sleep(2000);
  const full = await page.evaluate(() => {
    const c = window.gaitlab.three.renderer.domElement;
    return { width: c.width, css: c.clientWidth * window.devicePixelRatio,
      text: document.getElementById('drawing').textContent };
  });
  check(full.width === Math.floor(full.css), `"Full quality" draws at the full size (${full.width} of ${full.css}; "${full.text}")`);
  await page.uncheck('#full-quality');
  // the canvas takes the lower resolution at the next drawing, which may come a few animation
  // frames later while the simulation is behind (the page then draws at most 36 times a second)
  await page.waitForFunction(() => {
    const { adaptive, renderer } = window.gaitlab.three;
    const c = renderer.domElement;
    return adaptive.scale < 1 && c.width < c.clientWidth * window.devicePixelRatio;
  }, null, { timeout: 30000 }).catch(() => {});
  check(await page.evaluate(() => window.gaitlab.three.adaptive.scale < 1), 'unticked, it adapts again');

  // a recording is at the full size while it runs
  await page.click('#record-video');
  await sleep(1500);
  const rec = await page.evaluate(() => {
    const c = window.gaitlab.three.renderer.domElement;
    return { width: c.width, css: c.clientWidth * window.devicePixelRatio };
  });
  const [video] = await Promise.all([page.waitForEvent('download'), page.click('#record-video')]);
  await video.saveAs(path.join(out, 'recording.webm'));
  check(rec.width === Math.floor(rec.css), `a recording draws at the full size (${rec.width} of ${rec.css})`);

  // bad frames: a body whose pose is null (a diverged simulation: JSON has no NaN) stays where
  // it was while the others move; a frame with the wrong number of poses moves nothing
  const bad = await page.evaluate(() => {
    const g = window.gaitlab;
    const { THREE, bodies } = g.three;
    const at = (i) => bodies.position(i, new THREE.Vector3()).toArray();
    const before = [at(0), at(1)];
    const f = { ...g.frame, poses: g.frame.poses.slice() };
    f.poses.fill(null, 0, 7);
    f.poses[7] += 0.5;
    g.frame = f;
    g.three.render();
    const after = [at(0), at(1)];
    g.frame = { ...f, poses: f.poses.slice(0, 14).map((v) => (v === null ? v : v + 1)) };
    g.three.render();
    return { before, after, short: at(1), sent: f.poses.slice(7, 10) };
  });
  check(bad.after[0].join() === bad.before[0].join() && bad.after[1].join() === bad.sent.join(),
    `a null pose keeps its body in place while the others move (${bad.after[0].map((v) => v.toFixed(3))})`);
  check(bad.short.join() === bad.after[1].join(), 'a frame with too few poses moves nothing');
  check(pageErrors.length === 0, `no errors in the page (${pageErrors.join('; ')})`);
} finally {
  await browser.close();
}
served.child.kill('SIGINT');
const end = await Promise.race([served.exited, sleep(10000).then(() => null)]);
check(end !== null, `Ctrl-C quits gaitlab (status ${end ? end.code ?? end.signal : 'none after 10 s'})`);
finish();
