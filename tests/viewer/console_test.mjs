// The page and the terminal console at the same time: `gaitlab -i scripts/console.lua`, then
// sim:view() typed at the prompt gives the viewer's address; while the console waits for the
// next line, the page's commands play the simulation, change a parameter and pause it; a typed
// sim:run plays at real time; the session's run folder records the page's change and replays
// bit for bit. No browser: the page's requests are made with fetch.
//
// Usage: node console_test.mjs GAITLAB SOURCE_DIR OUT_DIR
import { spawn, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import net from 'node:net';
import path from 'node:path';
import { checker, freshDir, sleep } from './browser_lib.mjs';

const [gaitlab, source, out] = process.argv.slice(2);
freshDir(out);
const run = path.join(out, 'run');
const { check, finish } = checker();

const child = spawn(gaitlab, ['-i', path.join(source, 'tests/viewer/scripts/console.lua'),
  '--record', run], { stdio: ['pipe', 'pipe', 'pipe'] });
let stdout = '';
let stderr = '';
child.stdout.on('data', (d) => { stdout += d; });
child.stderr.on('data', (d) => { stderr += d; });
const exited = new Promise((resolve) => child.on('exit', (code) => resolve(code)));
// whatever happens to the test (a failed wait throws), gaitlab does not outlive it
process.on('exit', () => { if (child.exitCode === null) child.kill('SIGKILL'); });
async function waitFor(what, test, ms = 20000) {
  const end = Date.now() + ms;
  while (Date.now() < end) {
    if (test()) return true;
    await sleep(50);
  }
  console.log(`FAIL waiting for ${what}\nstdout:\n${stdout}\nstderr:\n${stderr}`);
  child.kill('SIGKILL');
  process.exit(1);
}
function type(line) { child.stdin.write(`${line}\n`); }

// sim:view{port =}: a bad port is refused as Lua refuses bad arguments; a free one is used
type('sim:view{port = 0}');
await waitFor('the bad port', () => /bad argument/.test(stderr));
check(/bad argument #1 to 'view' \(field 'port': a port number from 1 to 65535 expected \(got 0\)\)/.test(stderr),
  `sim:view{port = 0} is refused (${stderr.trim()})`);
const port = await new Promise((resolve) => {
  const s = net.createServer().listen(0, '127.0.0.1', () => { const p = s.address().port; s.close(() => resolve(p)); });
});
type(`print("at", sim:view{port = ${port}})`);
await waitFor('the address', () => /at\thttp:\/\/127\.0\.0\.1:\d+\//.test(stdout));
const url = stdout.match(/at\t(http:\/\/\S+)/)[1];
check(url === `http://127.0.0.1:${port}/`, `sim:view{port = ${port}} serves there (${url})`);
type(`sim:view{port = ${port === 65535 ? port - 1 : port + 1}}`);
await waitFor('another port refused', () => /serves http:\/\/127\.0\.0\.1:\d+\/ already/.test(stderr));
check(true, 'a second sim:view with another port says where the viewer serves already');
check(/viewer: http:\/\/127\.0\.0\.1:\d+\//.test(stderr), `sim:view() serves the viewer at ${url}`);
const post = async (command) => {
  const r = await fetch(`${url}api/command`, {
    method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(command),
  });
  return r.status;
};
const scene = await (await fetch(`${url}api/scene`)).json();
check(scene.simulation === 1 && scene.bodies.length === 5, 'the page gets the snake\'s scene');

// while the console waits for a line, the page plays the simulation
check(await post({ command: 'play' }) === 200, 'the page says play');
await sleep(800);
check(await post({ command: 'param', controller: 'sine', name: 'amplitude', value: 25 }) === 200,
  'the page sets sine.amplitude = 25');
await sleep(400);
check(await post({ command: 'pause' }) === 200, 'the page says pause');
await sleep(300);
type('print("t", sim.time, "amplitude", sim:status().controllers[1].params[1].value)');
await waitFor('the time', () => /^t\t[\d.]+\tamplitude\t25/m.test(stdout));
const t = Number(stdout.match(/^t\t([\d.]+)/m)[1]);
check(t > 0.5 && t < 5, `the simulation played while the console waited (t = ${t} s)`);
type('print("t again", sim.time)');
await waitFor('the time again', () => /^t again\t/m.test(stdout));
check(Number(stdout.match(/^t again\t([\d.]+)/m)[1]) === t, 'paused from the page, it stays paused');

// a typed run plays at real time while the view is open
const start = Date.now();
type('sim:run(0.5) print("ran")');
await waitFor('the run', () => /^ran$/m.test(stdout));
check(Date.now() - start >= 450, `a typed sim:run(0.5) plays at real time (${Date.now() - start} ms)`);
child.stdin.end();
const code = await exited;
check(code === 0, `the console ends with status 0 (got ${code})`);

const events = fs.readFileSync(path.join(run, 'events.csv'), 'utf8');
check(/,viewer,param,sine\.amplitude,25,/.test(events), 'events.csv records the page\'s change');
const replay = spawnSync(gaitlab, ['replay', run], { encoding: 'utf8' });
check(replay.status === 0 && /^replay identical/.test(replay.stdout),
  `the console session replays bit for bit (${(replay.stdout + replay.stderr).trim()})`);

// sim:view{host = "0.0.0.0"}: beyond loopback, a token every request must carry
{
  const c = spawn(gaitlab, ['-i', path.join(source, 'tests/viewer/scripts/console.lua'), '--no-record'],
    { stdio: ['pipe', 'pipe', 'pipe'] });
  let o = '';
  let e = '';
  c.stdout.on('data', (d) => { o += d; });
  c.stderr.on('data', (d) => { e += d; });
  const done = new Promise((resolve) => c.on('exit', resolve));
  c.stdin.write('print("at", sim:view{host = "0.0.0.0"})\n');
  const end = Date.now() + 15000;
  while (!/at\thttp/.test(o) && Date.now() < end) await sleep(50);
  const m = o.match(/at\t(http:\/\/127\.0\.0\.1:(\d+)\/\?token=([0-9a-f]{32}))/);
  check(m && /from another machine/.test(e), `sim:view{host = "0.0.0.0"} serves with a token (${o.trim()})`);
  if (m) {
    const without = await fetch(`http://127.0.0.1:${m[2]}/api/scene`);
    const withToken = await fetch(`http://127.0.0.1:${m[2]}/api/scene?token=${m[3]}`);
    check(without.status === 403 && withToken.status === 200,
      `without the token 403, with it 200 (${without.status}, ${withToken.status})`);
  }
  c.stdin.end();
  check(await done === 0, 'that console ends with status 0');
}

// without a viewer, sim:view() says where it works
const bad = path.join(out, 'view.lua');
fs.writeFileSync(bad, fs.readFileSync(path.join(source, 'tests/viewer/scripts/console.lua'), 'utf8') + 'sim:view()\n');
const noview = spawnSync(gaitlab, ['run', '--no-record', bad], { encoding: 'utf8' });
check(noview.status === 1 && /sim:view\(\): no viewer here: run the script with gaitlab run FILE --view/.test(noview.stderr),
  `sim:view() without a viewer is a clear error (${noview.stderr.trim()})`);

finish();
