// The page's adaptive drawing resolution (viewer/web/resolution.js) on simulated frame times,
// without a browser: frames slow in proportion to their pixels lower the resolution step by
// step down to the last step, fast ones raise it back to full; a scene that is slow only at
// full size settles one step below instead of flickering; frames that fewer pixels do not
// speed up keep the full resolution; pinned, it stays at full size whatever the frames take; a
// stall (a hidden tab) changes nothing; animation frames that draw nothing (idle) neither count
// as fast frames nor change anything. And how often the view may be drawn (DrawingRate): every
// frame, but about 36 a second while the simulation is behind its speed and for 5 s after.
//
// Usage: node resolution_test.mjs SOURCE_DIR
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const source = process.argv[2];
if (!source) {
  console.error('usage: node resolution_test.mjs SOURCE_DIR');
  process.exit(2);
}
const { AdaptiveResolution, kScales } = await import(
  pathToFileURL(path.join(source, 'viewer/web/resolution.js')).href);

let passed = 0;
let failed = 0;
function check(ok, what) {
  if (ok) passed++; else failed++;
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
}

// frames of cost(scale) ms each for `seconds`; the scales seen, one per frame
function play(a, clock, seconds, cost) {
  const seen = [];
  const end = clock.now + seconds * 1000;
  while (clock.now < end) {
    clock.now += Math.max(1000 / 60, cost(a.scale));   // a 60 Hz screen at best
    a.frame(clock.now);
    seen.push(a.scale);
  }
  return seen;
}

const renderer = {};   // the class only keeps it
{
  const clock = { now: 0 };
  const a = new AdaptiveResolution(renderer, { base: () => 2 });
  // slow in proportion to the pixels: 400 ms a frame at full size, down to the last step
  const seen = play(a, clock, 30, (x) => 400 * x * x);
  check(a.scale === kScales[kScales.length - 1] && a.pixelRatio() === 2 * a.scale,
    `slow frames lower the resolution to ${a.scale} (pixel ratio ${a.pixelRatio()} on a 2x screen)`);
  const steps = seen.filter((x, i) => i > 0 && x !== seen[i - 1]);
  check(steps.length === kScales.length - 1 && steps.every((x, i) => x === kScales[i + 1]),
    `one step at a time (${steps.join(', ')})`);
  // then fast frames: back to full size, one step at a time
  play(a, clock, 120, () => 8);
  check(a.scale === 1, `fast frames raise it back to full size (${a.scale})`);
}
{
  // pixels cost: 60 ms a frame at full size, proportional to the pixels (scale squared)
  const clock = { now: 0 };
  const a = new AdaptiveResolution(renderer, { base: () => 1 });
  const cost = (s) => 60 * s * s;
  play(a, clock, 30, cost);
  const seen = play(a, clock, 60, cost);
  check(seen.length / 60 >= 30, `a scene too slow at full size is drawn at 30 frames/s or more (${(seen.length / 60).toFixed(1)})`);
  check(seen.every((s) => s === seen[0]) && 60 * seen[0] ** 2 <= 1000 / 30,
    `it stays at the largest size that keeps up (${seen[0]})`);
}
{
  // a scene that is fast one step below full size and slow at full size: each try of full
  // size costs a slow half second, and the tries get rarer (4 s, 8 s, 16 s ... a minute)
  const clock = { now: 0 };
  const a = new AdaptiveResolution(renderer, { base: () => 1 });
  const cost = (s) => (s === 1 ? 80 : 10);
  const seen = play(a, clock, 300, cost);
  const changes = seen.filter((s, i) => i > 0 && s !== seen[i - 1]).length;
  const last = seen.slice(-Math.round(seen.length / 5));   // the last minute
  const lastChanges = last.filter((s, i) => i > 0 && s !== last[i - 1]).length;
  check(changes <= 16 && lastChanges <= 2,
    `it does not flicker (${changes} changes in 5 minutes, ${lastChanges} in the last one)`);
  const full = seen.filter((s) => s === 1).length;
  check(full < seen.length / 50, `it draws at the slow size rarely (${full} of ${seen.length} frames)`);
}
{
  // slow whatever the size (a busy machine): fewer pixels do not help, so it keeps the full
  // resolution nearly all the time, trying lower ones ever more rarely
  const clock = { now: 0 };
  const a = new AdaptiveResolution(renderer, { base: () => 1 });
  const seen = play(a, clock, 180, () => 120);
  const full = seen.filter((x) => x === 1).length;
  const changes = seen.filter((x, i) => i > 0 && x !== seen[i - 1]).length;
  check(full > 0.9 * seen.length && changes <= 12,
    `slow frames that fewer pixels do not speed up keep the full resolution (${full} of ${seen.length} frames, ${changes} changes in 3 minutes)`);
}
{
  const clock = { now: 0 };
  const a = new AdaptiveResolution(renderer, { base: () => 1 });
  let changes = 0;
  a.onchange = () => { changes++; };
  const release = a.pin();
  const seen = play(a, clock, 10, (x) => 200 * x * x);
  check(seen.every((s) => s === 1) && a.pinned, 'pinned, it draws at full size however slow the frames are');
  release();
  release();   // a second call changes nothing
  check(!a.pinned && a.pins === 0, 'released once and for all');
  play(a, clock, 5, (x) => 200 * x * x);
  check(a.scale < 1 && changes >= 3, `released, it adapts again (${a.scale})`);
  // a stall of 5 s (a hidden tab) is not a slow frame
  const before = a.scale;
  clock.now += 5000;
  a.frame(clock.now);
  play(a, clock, 0.4, () => 10);
  check(a.scale === before, `a stall changes nothing (${a.scale})`);
}
{
  // a page that draws only what changed (scene.js): animation frames that draw nothing are idle
  const clock = { now: 0 };
  const a = new AdaptiveResolution(renderer, { base: () => 1 });
  // slow drawings (200 ms at full size) with an idle 60 Hz frame after each: still lowered
  const end = clock.now + 30000;
  while (clock.now < end) {
    clock.now += 200 * a.scale * a.scale;
    a.frame(clock.now);
    clock.now += 1000 / 60;
    a.idle(clock.now);
  }
  check(a.scale < 0.5, `slow drawings between idle frames lower the resolution (${a.scale})`);
  // then paused: a minute of idle frames changes nothing, however fast they are
  const before = a.scale;
  let changes = 0;
  a.onchange = () => { changes++; };
  for (let t = 0; t < 60000; t += 1000 / 60) {
    clock.now += 1000 / 60;
    a.idle(clock.now);
  }
  check(a.scale === before && changes === 0, `a minute of idle frames changes nothing (${a.scale})`);
  // and drawing again, slow: the idle minute did not count as fast frames
  play(a, clock, 2, (x) => 200 * x * x);
  check(a.scale <= before, `drawing again after it keeps the resolution low (${a.scale})`);
}
{
  // how often the view may be drawn (DrawingRate): drawings in `seconds` of a `hz` screen
  const { DrawingRate } = await import(pathToFileURL(path.join(source, 'viewer/web/resolution.js')).href);
  const run = (r, clock, seconds, hz, behind, pinned = false) => {
    let drawn = 0;
    const end = clock.now + seconds * 1000;
    while (clock.now < end - 1e-9) {
      clock.now += 1000 / hz;
      if (r.allow(clock.now, behind(clock.now), pinned)) {
        drawn++;
        r.drew();
      }
    }
    return drawn / seconds;
  };
  const clock = { now: 0 };
  const r = new DrawingRate();
  const keeping = run(r, clock, 5, 60, () => false);
  check(keeping === 60,
    `a simulation that keeps its speed: every frame of a 60 Hz screen (${keeping} a second)`);
  const behind = run(r, clock, 10, 60, () => true);
  check(behind >= 35 && behind <= 37, `a simulation behind: about 36 drawings a second at 60 Hz (${behind})`);
  const fast = run(r, clock, 10, 144, () => true);
  check(fast >= 35 && fast <= 37, `... and at 144 Hz (${fast})`);
  const slow = run(r, clock, 10, 30, () => true);
  check(slow === 30, `a 30 Hz screen still draws every frame (${slow})`);
  const pinned = run(r, clock, 2, 60, () => true, true);
  check(pinned === 60, `pinned (a screenshot, a recording): every frame (${pinned})`);
  // caught up: 5 s more at 36, then every frame again
  const after = run(r, clock, 5, 60, () => false);
  const later = run(r, clock, 3, 60, () => false);
  check(after >= 35 && after <= 37 && later >= 59,
    `caught up: 36 a second for 5 s more (${after}), then every frame (${later} in the seconds after)`);
  // what counts as behind
  const state = (o) => ({ playing: true, speed: 1, delay: 0, measured: 0.5, ...o });
  check(DrawingRate.behind(state({})) && !DrawingRate.behind(state({ measured: 0.97 })) &&
    !DrawingRate.behind(state({ playing: false })) && !DrawingRate.behind(state({ speed: 'max' })) &&
    !DrawingRate.behind(state({ delay: 0.001 })) && !DrawingRate.behind(state({ measured: null })) &&
    !DrawingRate.behind(undefined),
  'behind: playing at a finite speed without a delay, measured below 95 % of it (not paused, ' +
    'as fast as possible, slowed by a delay, or not measured yet)');
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
