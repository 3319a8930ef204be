// What the viewer's end-to-end tests share: their arguments, finding Debian's chromium (exit 77,
// ctest's "skipped", only when it is not installed), playwright-core from viewer/web's
// node_modules, a fresh output folder, gaitlab started and the address it prints, and the
// ok/FAIL lines with their count.
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import fs from 'node:fs';
import path from 'node:path';

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// GAITLAB SOURCE_DIR OUT_DIR [more]: the arguments, or the usage and exit 2 when one is missing
export function testArgs(script) {
  const args = process.argv.slice(2);
  if (!args[0] || !args[1] || !args[2]) {
    console.error(`usage: node ${script} GAITLAB SOURCE_DIR OUT_DIR`);
    process.exit(2);
  }
  return args;
}

// the chromium to use ($CHROMIUM, else Debian's); exit 77 when there is none
export function findChromium() {
  const chromium = process.env.CHROMIUM || '/usr/bin/chromium';
  if (!fs.existsSync(chromium)) {
    console.log(`SKIP: no chromium at ${chromium} (apt-get install chromium; tools/setup.sh does)`);
    process.exit(77);
  }
  return chromium;
}

// playwright-core as viewer/web installs it; a failure (exit 1) when it is missing
export function loadPlaywright(source) {
  const require = createRequire(path.join(source, 'viewer/web/package.json'));
  try {
    return require('playwright-core');
  } catch (e) {
    console.error('FAIL: playwright-core is missing: run tools/setup.sh (npm ci in viewer/web)');
    process.exit(1);
  }
}

// headless chromium drawing WebGL in software and compositing the page in software, as chromium
// does on a machine without a GPU (and as `gaitlab view RUN --video` runs it): composited by
// SwiftShader too, every frame of the page was read back (docs/performance.md §9)
export function launchChromium(playwright, chromium) {
  return playwright.chromium.launch({
    executablePath: chromium,
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist',
      '--disable-gpu-compositing'],
  });
}

// OUT_DIR emptied
export function freshDir(out) {
  fs.rmSync(out, { recursive: true, force: true });
  fs.mkdirSync(out, { recursive: true });
}

// check(ok, what) prints "ok   what" or "FAIL what"; finish() prints the count and exits 0 only
// when nothing failed
export function checker() {
  let passed = 0;
  let failed = 0;
  return {
    check(ok, what) {
      if (ok) passed++; else failed++;
      console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
    },
    finish() {
      console.log(`${passed} passed, ${failed} failed`);
      process.exit(failed === 0 ? 0 : 1);
    },
  };
}

const children = [];
// whatever happens to a test (a failed wait throws), the gaitlabs it started do not outlive it
process.on('exit', () => { for (const c of children) if (c.exitCode === null) c.kill('SIGKILL'); });

// starts gaitlab with args (options as spawn's) and waits for the address it prints after
// `label` ("viewer: http://..."); { child, out, err, url, exited } where exited resolves to
// { code, signal }. No address within 10 s: the failure and exit 1
export async function serve(gaitlab, args, label, options = {}) {
  const child = spawn(gaitlab, args, { ...options, stdio: ['ignore', 'pipe', 'pipe'] });
  children.push(child);
  const io = { out: '', err: '', url: null, child };
  child.stdout.on('data', (d) => { io.out += d; });
  child.stderr.on('data', (d) => { io.err += d; });
  io.exited = new Promise((resolve) => child.on('exit', (code, signal) => resolve({ code, signal })));
  for (let i = 0; i < 100 && !io.url; ++i) {
    const m = io.err.match(new RegExp(`${label}: (http://\\S+)`));
    if (m) io.url = m[1]; else await sleep(100);
  }
  if (!io.url) {
    console.error(`FAIL: gaitlab printed no address:\n${io.err}`);
    process.exit(1);
  }
  return io;
}
