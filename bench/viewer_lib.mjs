// What the viewer benchmarks (viewer_fps.mjs, viewer_parts.mjs, viewer_floor.mjs) share: Debian's
// headless chromium with WebGL in software, the crowd of snakes served by gaitlab, and the CPU
// time of the processes involved.
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import fs from 'node:fs';
import path from 'node:path';

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// the chromium to drive (CHROMIUM, default Debian's); exits with how to install it when missing
export function findChromium() {
  const chromium = process.env.CHROMIUM || '/usr/bin/chromium';
  if (!fs.existsSync(chromium)) {
    console.error(`no chromium at ${chromium} (apt-get install chromium; tools/setup.sh does)`);
    process.exit(1);
  }
  return chromium;
}

// playwright-core as the page's npm set-up installed it (viewer/web/node_modules)
export function loadPlaywright(source) {
  return createRequire(path.resolve(source, 'viewer/web/package.json'))('playwright-core');
}

// chromium with WebGL drawn by SwiftShader, plus the given switches ("-" or "" for none); by
// default --disable-gpu-compositing, as `gaitlab view RUN --video` and the browser tests run it
export function launchBrowser(playwright, chromium, extra = '--disable-gpu-compositing') {
  return playwright.chromium.launch({
    executablePath: chromium,
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
      '--ignore-gpu-blocklist', ...extra.split(/\s+/).filter((a) => a && a !== '-')],
  });
}

// `gaitlab run bench/lua/crowd.lua --view` with `robots` snakes of 8 modules; resolves to
// { child, url } once gaitlab printed the page's address (rejects after 30 s without it)
export async function startCrowd(gaitlab, source, robots) {
  const child = spawn(gaitlab, ['run', path.join(source, 'bench/lua/crowd.lua'), '--view',
    '--no-record', '--no-progress', '--', String(robots), '8', '600'],
  { stdio: ['ignore', 'ignore', 'pipe'] });
  let stderr = '';
  child.stderr.on('data', (d) => { stderr += d; });
  for (let i = 0; i < 300; ++i) {
    const m = stderr.match(/viewer: (http:\/\/\S+)/);
    if (m) return { child, url: m[1] };
    await sleep(100);
  }
  child.kill('SIGINT');
  throw new Error(`gaitlab printed no address:\n${stderr}`);
}

// CPU seconds of a process (all its threads) so far, or 0 when it is gone
export function cpuSeconds(pid) {
  try {
    const stat = fs.readFileSync(`/proc/${pid}/stat`, 'utf8');
    const f = stat.slice(stat.lastIndexOf(')') + 2).split(' ');
    return (Number(f[11]) + Number(f[12])) / 100;   // utime, stime in USER_HZ ticks
  } catch (e) {
    return 0;
  }
}

// chromium's processes under `root` (not `skip`), by kind: renderer, gpu, other
export function chromiumProcesses(root = process.pid, skip = -1) {
  const parent = new Map();
  for (const d of fs.readdirSync('/proc')) {
    if (!/^\d+$/.test(d)) continue;
    try {
      const stat = fs.readFileSync(`/proc/${d}/stat`, 'utf8');
      parent.set(Number(d), Number(stat.slice(stat.lastIndexOf(')') + 2).split(' ')[1]));
    } catch (e) { /* gone */ }
  }
  const under = (pid) => {
    for (let p = pid; p > 1; p = parent.get(p)) if (p === root) return true;
    return false;
  };
  const kinds = { renderer: [], gpu: [], other: [] };
  for (const pid of parent.keys()) {
    if (pid === root || pid === skip || !under(pid)) continue;
    let cmd = '';
    try { cmd = fs.readFileSync(`/proc/${pid}/cmdline`, 'utf8'); } catch (e) { continue; }
    if (cmd.includes('--type=renderer')) kinds.renderer.push(pid);
    else if (cmd.includes('--type=gpu-process')) kinds.gpu.push(pid);
    else kinds.other.push(pid);
  }
  return kinds;
}

// the page's own files (index.html, *.js, style.css) served to `page` from dir instead of those
// built into gaitlab; the libraries (lib/) and the API still come from gaitlab
export async function servePageFrom(page, dir) {
  if (!fs.existsSync(path.join(dir, 'index.html'))) {
    throw new Error(`WEB: ${dir} has no index.html (a copy of viewer/web expected)`);
  }
  const types = { '.html': 'text/html', '.js': 'text/javascript', '.css': 'text/css' };
  const file = (url) => path.basename(url.pathname) || 'index.html';
  await page.route((url) => !url.pathname.includes('/lib/') && !url.pathname.includes('/api/') &&
    fs.existsSync(path.join(dir, file(url))) && types[path.extname(file(url))] !== undefined,
  (route) => {
    const f = file(new URL(route.request().url()));
    route.fulfill({ body: fs.readFileSync(path.join(dir, f)), contentType: types[path.extname(f)] });
  });
}
