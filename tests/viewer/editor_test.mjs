// The environment editor end to end, in Debian's headless chromium (playwright-core):
// `gaitlab edit OUT/world.xml --robot snake.robot.xml` makes the file (saying so) and serves the
// editor; the test places the robot, adds a box, drags it in the top view, sets its size and
// friction, sees a bad friction refused by name (and not saved), saves, and then gaitlab loads
// the file: the box is where it was dragged (the world's listing from Lua) and a headless
// `gaitlab run` of a simulation file with it runs. Then, under `gaitlab run --view`: the
// contact points appear when the robot lies on the floor, the delay is set from the page, and
// "Edit world" opens the simulation's world and saves it beside the script.
//
// Usage: node editor_test.mjs GAITLAB SOURCE_DIR OUT_DIR [edit|view]
// (edit: gaitlab edit and loading what it saved; view: under --view; both by default)
// Exit 77 (ctest: skipped) only when no chromium is installed.
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { checker, findChromium, freshDir, launchChromium, loadPlaywright, serve as serveAt, sleep, testArgs } from './browser_lib.mjs';

const [gaitlab, source, out, part] = testArgs('editor_test.mjs');
const chromium = findChromium();
const playwright = loadPlaywright(source);
freshDir(out);
const { check, finish } = checker();
// starts gaitlab in OUT_DIR and waits for the address it prints after `label`
const serve = (args, label) => serveAt(gaitlab, args, label, { cwd: out });

const browser = await launchChromium(playwright, chromium);
// prints where "box 1" of the environment file arg[1] is, and the world
const listing = `local w = assert(gaitlab.world.load(arg[1]))
local lo, hi = { math.huge, math.huge, math.huge }, { -math.huge, -math.huge, -math.huge }
for _, t in ipairs(w:triangles()) do
  if t.object == "box 1" then
    for i = 1, #t.vertices, 3 do
      for k = 1, 3 do
        lo[k] = math.min(lo[k], t.vertices[i + k - 1]); hi[k] = math.max(hi[k], t.vertices[i + k - 1])
      end
    end
  end
end
print(string.format("box 1 from %.3f %.3f %.3f to %.3f %.3f %.3f", lo[1], lo[2], lo[3], hi[1], hi[2], hi[3]))
print(tostring(w))
`;
const robotFile = path.join(source, 'examples/walk/snake.robot.xml');
const world = path.join(out, 'world.xml');
try {
  if (part !== 'view') {
  // ---- gaitlab edit: a new file ----
  fs.copyFileSync(path.join(source, 'examples/terrain.png'), path.join(out, 'terrain.png'));
  const edit = await serve(['edit', 'world.xml', '--robot', robotFile], 'editor');
  check(/world\.xml does not exist: creating it/.test(edit.err) && fs.existsSync(world),
    'gaitlab edit says it creates the missing file, and does');
  const initial = fs.readFileSync(world, 'utf8');
  const page = await browser.newPage({ viewport: { width: 1280, height: 760 } });
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(e.message));
  await page.goto(edit.url, { timeout: 90000 });
  await page.waitForFunction(() => window.gaitlab.editor && window.gaitlab.editor.open, null, { timeout: 20000 });
  check(await page.isVisible('#editor-top') && !(await page.isVisible('#scene')),
    'the page opens in the editor: top, side and 3D views');
  const ed = (fn, arg) => page.evaluate(fn, arg);
  const checks = () => ed(() => window.gaitlab.editor.checks);
  const waitCheck = async (k) => {
    try {
      await page.waitForFunction((c) => window.gaitlab.editor.checks > c, k, { timeout: 10000 });
    } catch (e) {
      await page.screenshot({ path: path.join(out, 'editor-failed.png') });
      console.log(`FAIL waiting for a check: ${await page.textContent('#editor-status')}; ${pageErrors.join('; ')}`);
      throw e;
    }
  };

  // place the robot (it was not placed in the new file)
  let n = await checks();
  await page.selectOption('#editor-list', 'rsnake');
  await waitCheck(n);
  check(await ed(() => window.gaitlab.editor.env.placements[0].robot === 'snake'), 'the robot is placed');

  // add a box, make it 0.2 × 0.6 × 0.08 m
  n = await checks();
  await page.selectOption('#editor-kind', 'box');
  await page.click('#editor-add');
  await waitCheck(n);
  for (const [k, v] of [['size.0', '0.2'], ['size.1', '0.6'], ['size.2', '0.08']]) {
    n = await checks();
    await page.fill(`#editor-form input[data-field="${k}"]`, v);
    await page.press(`#editor-form input[data-field="${k}"]`, 'Enter');
    await waitCheck(n);
  }
  let box = await ed(() => window.gaitlab.editor.env.objects[0]);
  check(box.kind === 'box' && box.size.join(' ') === '0.2 0.6 0.08', `a box is added and resized (${JSON.stringify(box)})`);
  // its height: on the floor
  n = await checks();
  await page.fill('#editor-form input[data-field="position.2"]', '0.04');
  await page.press('#editor-form input[data-field="position.2"]', 'Enter');
  await waitCheck(n);

  const over = await page.textContent('#editor-status');
  check(/^the engine takes it, but: body '.*' of robot 'snake' starts .* mm deep inside box 1/.test(over),
    `on the robot, the box is warned of as gaitlab run would (${over})`);
  await page.screenshot({ path: path.join(out, 'editor-overlap.png') });

  // drag it in the top view to x = 1, y = 0.1 (the grid snaps to 5 cm)
  box = await ed(() => window.gaitlab.editor.env.objects[0]);
  const from = await ed(([x, y, z]) => window.gaitlab.editor.toScreen('top', x, y, z), box.position);
  const to = await ed(() => window.gaitlab.editor.toScreen('top', 1.0, 0.1, 0.04));
  // grab it away from the gizmo's handles (they point to +x and +y from its centre)
  const dx = -8, dy = 14;
  n = await checks();
  await page.mouse.move(from.x + dx, from.y + dy);
  await page.mouse.down();
  for (let i = 1; i <= 10; ++i) {
    await page.mouse.move(from.x + dx + (to.x - from.x) * i / 10, from.y + dy + (to.y - from.y) * i / 10);
  }
  await page.mouse.up();
  await waitCheck(n);
  box = await ed(() => window.gaitlab.editor.env.objects[0]);
  check(await page.textContent('#editor-status') === 'the engine takes it: 1 solid', 'clear of the robot, no warning');
  check(Math.abs(box.position[0] - 1.0) < 1e-9 && Math.abs(box.position[1] - 0.1) < 1e-9 && box.position[2] === 0.04,
    `dragged in the top view, the box is at ${box.position.join(' ')} (1 0.1 0.04 expected)`);

  // a bad friction: refused by the engine, naming the box and the field; nothing saved
  n = await checks();
  await page.fill('#editor-form input[data-field="friction"]', '-1');
  await page.press('#editor-form input[data-field="friction"]', 'Enter');
  await waitCheck(n);
  const refused = await page.textContent('#editor-status');
  check(refused === 'box 1 friction must be in [0, 1] (got -1)', `a friction of -1 is refused: "${refused}"`);
  check(await page.isVisible('.editor-field.bad input[data-field="friction"]'), 'the friction field is marked');
  await page.screenshot({ path: path.join(out, 'editor-refused.png') });
  await page.click('#editor-save');
  await page.waitForFunction(() => /not saved/.test(document.getElementById('editor-status').textContent));
  check(fs.readFileSync(world, 'utf8') === initial, `saving is refused and the file is untouched (${await page.textContent('#editor-status')})`);
  // NaN too
  n = await checks();
  await page.fill('#editor-form input[data-field="friction"]', 'nan');
  await page.press('#editor-form input[data-field="friction"]', 'Enter');
  await waitCheck(n);
  check(await page.textContent('#editor-status') === 'box 1 friction must be in [0, 1] (got nan)', 'a friction of nan is refused');

  // the friction it should have, and the floor's
  n = await checks();
  await page.fill('#editor-form input[data-field="friction"]', '0.3');
  await page.press('#editor-form input[data-field="friction"]', 'Enter');
  await waitCheck(n);
  n = await checks();
  await page.fill('#editor-floor-friction', '0.7');
  await page.press('#editor-floor-friction', 'Enter');
  await waitCheck(n);
  check(/the engine takes it/.test(await page.textContent('#editor-status')), 'friction 0.3 is taken');
  // the floor's contact from the page: compliant by default (the empty fields show the
  // defaults), rigid with the check box (its fields emptied and closed), then a stiffness and a
  // damping of its own
  check(await page.getAttribute('#editor-floor-stiffness', 'placeholder') === '1e5 (default)', 'the stiffness field shows the default');
  n = await checks();
  await page.fill('#editor-floor-stiffness', '1e4');
  await page.press('#editor-floor-stiffness', 'Enter');
  await waitCheck(n);
  check(/the engine takes it/.test(await page.textContent('#editor-status')), 'a stiffness alone is taken (the damping its default)');
  n = await checks();
  await page.check('#editor-floor-rigid');
  await waitCheck(n);
  check(/the engine takes it/.test(await page.textContent('#editor-status')), 'a rigid floor is taken');
  check(await page.inputValue('#editor-floor-stiffness') === '' && await page.isDisabled('#editor-floor-stiffness') &&
    await page.isDisabled('#editor-floor-damping'), 'a rigid floor empties and closes the stiffness and damping');
  n = await checks();
  await page.uncheck('#editor-floor-rigid');
  await waitCheck(n);
  check(!(await page.isDisabled('#editor-floor-stiffness')), 'compliant again, the stiffness opens');
  n = await checks();
  await page.fill('#editor-floor-stiffness', '1e4');
  await page.press('#editor-floor-stiffness', 'Enter');
  await waitCheck(n);
  n = await checks();
  await page.fill('#editor-floor-damping', '20');
  await page.press('#editor-floor-damping', 'Enter');
  await waitCheck(n);
  check(/the engine takes it/.test(await page.textContent('#editor-status')), 'stiffness 1e4 with damping 20 is taken');
  // a heightfield from a PNG of the folder, put behind the robot
  n = await checks();
  await page.selectOption('#editor-kind', 'heightfield');
  await page.click('#editor-add');
  await waitCheck(n);
  n = await checks();
  await page.fill('#editor-form input[data-field="position.0"]', '-1');
  await page.press('#editor-form input[data-field="position.0"]', 'Enter');
  await waitCheck(n);
  const terrain = await page.textContent('#editor-status');
  check(terrain === 'the engine takes it: 2 solids' && await page.inputValue('#editor-form select[data-field="image"]') === 'terrain.png',
    `a heightfield from terrain.png is added (${terrain})`);
  // a heightfield from numbers: added from the PNG, switched to numbers, a bad grid refused
  n = await checks();
  await page.click('#editor-add');
  await waitCheck(n);
  n = await checks();
  await page.click('#editor-heights-numbers');
  await waitCheck(n);
  n = await checks();
  await page.fill('#editor-form input[data-field="position.1"]', '2');
  await page.press('#editor-form input[data-field="position.1"]', 'Enter');
  await waitCheck(n);
  n = await checks();
  await page.fill('#editor-heights', '0 0 0\n0 x 0\n0 0');
  await page.locator('#editor-heights').dispatchEvent('change');
  await waitCheck(n);
  const ragged = await page.textContent('#editor-status');
  check(/^heightfield 2 heights: row 2 column 2: a height in m expected \(got "x"\)$/.test(ragged) &&
    await page.isVisible('.editor-heights.bad'), `a height that is not a number is refused by row and column (${ragged})`);
  n = await checks();
  await page.fill('#editor-heights', '0 0 0\n0 0.03 0');
  await page.locator('#editor-heights').dispatchEvent('change');
  await waitCheck(n);
  n = await checks();
  await page.fill('#editor-heights', '0 0.01 0.02 0.03\n0.005 0.015 0.025 0.035\n-0.01 0 0.0125 0.1');
  await page.locator('#editor-heights').dispatchEvent('change');
  await waitCheck(n);
  n = await checks();
  await page.fill('#editor-heights-cell', '0.2');
  await page.press('#editor-heights-cell', 'Enter');
  await waitCheck(n);
  const grid = await page.evaluate(() => window.gaitlab.editor.env.objects.filter((o) => o.kind === 'heightfield')[1]);
  const numbers = await page.textContent('#editor-status');
  check(/^the engine takes it/.test(numbers) && grid.length === 0.6 && grid.width === 0.4 && grid.heights.length === 3,
    `a 3 × 4 grid of heights with 0.2 m cells is taken (${numbers}; ${grid.length} × ${grid.width} m)`);
  // the box selected again (the picture below looks for it)
  await page.selectOption('#editor-list', 'o0');
  await page.waitForFunction(() => window.gaitlab.editor.selected && window.gaitlab.editor.selected.object === 0);
  await sleep(200);
  // a saved name outside the folder is refused
  await page.fill('#editor-name', '../elsewhere.xml');
  await page.click('#editor-save');
  await page.waitForFunction(() => /not saved: file: a file name in the folder/.test(document.getElementById('editor-status').textContent));
  check(!fs.existsSync(path.join(out, '..', 'elsewhere.xml')), 'a name outside the folder is refused');
  await page.fill('#editor-name', 'world.xml');
  await page.click('#editor-save');
  await page.waitForFunction(() => /^saved world\.xml/.test(document.getElementById('editor-status').textContent));
  await page.screenshot({ path: path.join(out, 'editor.png') });
  const saved = fs.readFileSync(world, 'utf8');
  check(/<floor friction="0\.7" stiffness="10000" damping="20"\/>/.test(saved) && /<box size="0\.2 0\.6 0\.08" position="1 0\.1 0\.04" friction="0\.3"\/>/.test(saved) &&
    /<place robot="snake" position="0 0 0"\/>/.test(saved) && /<heightfield [^>]*position="-1 0 0"[^>]* image="terrain\.png"\/>/.test(saved), `the file holds the box, the floor and the robot's place:\n${saved}`);
  // the grid's heights, as typed
  const stored = saved.match(/<heightfield length="0\.6" width="0\.4"[^>]*samples="4 3"[^>]*>\s*<heights>([^<]*)<\/heights>/);
  const back = stored ? stored[1].trim().split(/\s+/).map(Number) : [];
  const typedIn = [0, 0.01, 0.02, 0.03, 0.005, 0.015, 0.025, 0.035, -0.01, 0, 0.0125, 0.1];
  check(back.length === 12 && back.every((v, i) => v === typedIn[i]), `the file holds the grid's 12 heights as typed (${back.join(' ')})`);
  // the picture: the box drawn in the top view (blue: selected)
  const blue = await page.evaluate(() => {
    const c = document.getElementById('editor-top');
    const g = document.createElement('canvas');
    g.width = c.width; g.height = c.height;
    const x = g.getContext('2d');
    x.drawImage(c, 0, 0);
    const d = x.getImageData(0, 0, g.width, g.height).data;
    let k = 0;
    for (let i = 0; i < d.length; i += 4) if (d[i + 2] > 150 && d[i] < 120) k++;
    return k;
  });
  check(blue > 200, `the selected box is drawn in the top view (${blue} blue pixels)`);
  check(pageErrors.length === 0, `no errors in the page (${pageErrors.join('; ')})`);
  await page.close();
  edit.child.kill('SIGINT');
  check((await edit.exited).code === 0, 'Ctrl-C ends gaitlab edit with status 0');

  // ---- gaitlab loads it: the world's listing, and a headless run ----
  const lua = path.join(out, 'list.lua');
  fs.writeFileSync(lua, listing);
  const listed = spawnSync(gaitlab, ['run', '--no-record', lua, world], { encoding: 'utf8' });
  check(listed.status === 0 && /1 box, 2 heightfields/.test(listed.stdout) && /box 1 from 0\.900 -0\.200 0\.000 to 1\.100 0\.400 0\.080/.test(listed.stdout),
    `gaitlab loads the saved world: ${listed.stdout.trim()} ${listed.stderr.trim()}`);
  const actuation = path.join(source, 'examples/walk/snake.actuation.xml');
  fs.writeFileSync(path.join(out, 'edited.xml'), `<?xml version="1.0"?>
<gaitlab version="1">
    <simulation name="edited" duration="1">
        <environment file="world.xml"/>
        <robot file="${robotFile}" actuation="${actuation}"/>
    </simulation>
</gaitlab>
`);
  const ran = spawnSync(gaitlab, ['run', '--no-record', path.join(out, 'edited.xml')], { encoding: 'utf8' });
  check(ran.status === 0 && ran.stderr === '', `gaitlab run of a simulation file with it runs, the robot clear of the box (${ran.stderr.trim()})`);

  }
  if (part !== 'edit') {
  const pageErrors = [];
  const lua = path.join(out, 'list.lua');
  fs.writeFileSync(lua, listing);
  // ---- under --view: contact points, the delay, and "Edit world" ----
  fs.copyFileSync(path.join(source, 'tests/viewer/scripts/walk.lua'), path.join(out, 'walk.lua'));
  const view = await serve(['run', 'walk.lua', '--view', '--no-record', '--no-progress', '--', '30'], 'viewer');
  const p2 = await browser.newPage({ viewport: { width: 1280, height: 760 } });
  p2.on('pageerror', (e) => pageErrors.push(e.message));
  await p2.goto(view.url, { timeout: 90000 });
  await p2.waitForFunction(() => window.gaitlab && window.gaitlab.drawn > 5, null, { timeout: 30000 });
  const f0 = await p2.evaluate(() => window.gaitlab.frame);
  check(f0.contacts === undefined && f0.state.contacts === false, 'frames carry no contact points while the box is off');
  await p2.check('#contacts');
  await p2.waitForFunction(() => window.gaitlab.contacts > 3, null, { timeout: 10000 });
  const contacts = await p2.evaluate(() => window.gaitlab.frame.contacts);
  let onFloor = 0;
  for (let i = 0; i < contacts.length; i += 7) if (Math.abs(contacts[i + 2]) < 0.003) onFloor++;
  check(onFloor >= 3, `contact points appear where the snake lies on the floor (${contacts.length / 7} points, ${onFloor} at z = 0)`);
  const poses = await p2.evaluate(() => window.gaitlab.frame.poses);
  let far = 0;
  for (let i = 0; i < contacts.length; i += 7) {
    let near = Infinity;
    for (let b = 0; b < poses.length; b += 7) {
      near = Math.min(near, Math.hypot(contacts[i] - poses[b], contacts[i + 1] - poses[b + 1], contacts[i + 2] - poses[b + 2]));
    }
    far = Math.max(far, near);
  }
  check(far < 0.06, `each contact point is at a body of the snake or at the box it may push (at most ${far.toFixed(3)} m from a body's centre)`);
  await p2.click('#follow');
  await p2.evaluate(() => {
    const { camera, controls } = window.gaitlab.three;
    controls.target.set(0.3, 0, 0);
    camera.position.set(0.3, -0.5, 0.35);
  });
  await sleep(300);
  await p2.screenshot({ path: path.join(out, 'viewer-contacts.png') });
  await p2.uncheck('#contacts');
  await p2.waitForFunction(() => window.gaitlab.frame.contacts === undefined);
  check(true, 'unticked, frames carry no contact points again');
  // the delay: 5 ms between steps slows the run down
  await p2.fill('#delay', '5');
  await p2.press('#delay', 'Enter');
  await p2.waitForFunction(() => window.gaitlab.frame.state.delay === 0.005);
  await sleep(1200);
  const slow = await p2.evaluate(() => window.gaitlab.frame.state.measured);
  check(slow < 0.5, `a delay of 5 ms a step is set from the page, and the run slows down (${slow}x real time)`);
  await p2.fill('#delay', '0');
  await p2.press('#delay', 'Enter');
  await p2.waitForFunction(() => window.gaitlab.frame.state.delay === 0);
  // Edit world: the simulation's world, saved beside the script
  await p2.click('#edit-world');
  await p2.waitForFunction(() => window.gaitlab.editor.open);
  const env = await p2.evaluate(() => window.gaitlab.editor.env);
  check(env.objects.map((o) => o.kind).join(',') === 'box,box,ramp,stairs' && env.placements[0].robot === 'snake' &&
    await p2.isVisible('#editor-leave'), 'Edit world opens the simulation\'s world: two boxes, the ramp, the stairs, the snake');
  await p2.click('#editor-save');
  await p2.waitForFunction(() => /^saved walk\.environment\.xml/.test(document.getElementById('editor-status').textContent));
  const again = spawnSync(gaitlab, ['run', '--no-record', lua, path.join(out, 'walk.environment.xml')], { encoding: 'utf8' });
  check(/2 boxes.*1 ramp.*1 stairs|boxes/.test(again.stdout) && /box 1 from 0\.250 -0\.350 0\.000 to 0\.350 -0\.250 0\.050/.test(again.stdout),
    `it saves walk.environment.xml beside the script, and gaitlab loads it (${again.stdout.trim()})`);
  await p2.click('#editor-leave');
  check(await p2.isVisible('#scene'), 'Leave editor shows the simulation again');
  check(pageErrors.length === 0, `no errors in the pages (${pageErrors.join('; ')})`);
  view.child.kill('SIGINT');
  await view.exited;
  }
} finally {
  await browser.close();
}
finish();
