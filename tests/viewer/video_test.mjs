// gaitlab view RUN --video OUT.webm: the run rendered to a video in Debian's headless chromium,
// without a window. The file must be a WebM (EBML header, DocType webm), of a fair size, with
// frames spread over about the run's duration; gaitlab says where it wrote it and leaves no
// partial file. (Without chromium, run_view_test.cpp checks the message saying how to install
// it.)
//
// Usage: node video_test.mjs GAITLAB SOURCE_DIR OUT_DIR
// Exit 77 (ctest: skipped) only when no chromium is installed.
import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { checker, findChromium, freshDir, testArgs } from './browser_lib.mjs';
import { webmInfo } from './webm.mjs';

const [gaitlab, source, out] = testArgs('video_test.mjs');
const chromium = findChromium();
freshDir(out);
const { check, finish } = checker();

const walk = path.join(source, 'tests/viewer/scripts/walk.lua');
const rec = spawnSync(gaitlab, ['run', walk, '--record', 'walk', '--', '1'], { cwd: out, encoding: 'utf8' });
if (rec.status !== 0) {
  console.error(`FAIL: gaitlab run failed: ${rec.stderr}`);
  process.exit(1);
}
const times = fs.readFileSync(path.join(out, 'walk/data.csv'), 'utf8').trimEnd().split('\n').slice(1)
  .map((l) => Number(l.split(',')[0]));
const duration = times[times.length - 1] - times[0];

const started = Date.now();
const r = spawnSync(gaitlab, ['view', 'walk', '--video', 'walk.webm', '--size', '640x360'],
  { cwd: out, encoding: 'utf8', env: { ...process.env, GAITLAB_CHROMIUM: chromium }, timeout: 100000 });
const wall = (Date.now() - started) / 1000;
check(r.status === 0, `gaitlab view --video ends with status 0 in ${wall.toFixed(1)} s (${r.status}: ${r.stderr.trim()})`);
check(/^wrote walk\.webm$/m.test(r.stderr), 'gaitlab says where it wrote the video');
const file = path.join(out, 'walk.webm');
const bytes = fs.existsSync(file) ? fs.readFileSync(file) : Buffer.alloc(0);
const info = webmInfo(bytes);
check(info.ok, `the file is a WebM (DocType ${info.docType}, ${info.blocks} frames) ${info.error}`);
check(bytes.length > 10000, `it is not trivial (${bytes.length} bytes)`);
check(info.blocks >= 5, `it has frames (${info.blocks})`);
check(info.seconds > 0.6 * duration && info.seconds < duration + 1.5,
  `it lasts about the run's ${duration.toFixed(2)} s (${info.seconds.toFixed(2)} s)`);
check(!fs.existsSync(`${file}.part`), 'no partial file is left');
const run = JSON.parse(fs.readFileSync(path.join(out, 'walk/run.json'), 'utf8'));
check(run.status === 'finished' && fs.readdirSync(path.join(out, 'walk')).length === 6,
  'the run folder is as it was');

// a folder that is not a run: the file it lacks, no video, status 1
fs.mkdirSync(path.join(out, 'empty'));
const bad = spawnSync(gaitlab, ['view', 'empty', '--video', 'bad.webm'],
  { cwd: out, encoding: 'utf8', env: { ...process.env, GAITLAB_CHROMIUM: chromium } });
check(bad.status === 1 && /run\.json/.test(bad.stderr) && !fs.existsSync(path.join(out, 'bad.webm')),
  `a folder that is not a run: status ${bad.status}, ${bad.stderr.trim()}`);

finish();
