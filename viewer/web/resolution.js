// Adaptive drawing resolution for a three.js renderer (docs/viewer.md, "Drawing"). When frames
// take longer than the budget (33 ms: 30 frames per second), the view is drawn with fewer
// pixels, step by step (the canvas keeps its size on the page; the browser scales the picture
// up), and with more again when there is room. Pinned (the page's "Full quality" box, a
// screenshot, a recording, a video), it draws at the full size and does not adapt.
//
// How it decides: over windows of at least half a second (and 8 frames), the mean time between
// two animation frames. Above the budget: one step down; if the frames are not at least 15 %
// shorter after it, pixels are not what is slow, and it goes back up and does not try lower
// for a while. Below 60 % of the budget for two windows in a row: one step up, unless that
// step went down again soon after the last time it was tried (then it waits twice as long
// before trying again, up to a minute), so it does not oscillate. Animation frames that draw
// nothing (nothing changed: a paused simulation, a still camera) are told with idle(): the
// time up to them is not drawing time, so it leaves the window, and a pause changes nothing.
// DrawingRate (below) says how often the view may be drawn while the simulation is behind.

export const kScales = [1, 0.8, 0.64, 0.5, 0.4, 0.32, 0.25];

export class AdaptiveResolution {
  // renderer: a THREE.WebGLRenderer; budgetMs: the longest frame wanted
  constructor(renderer, { budgetMs = 1000 / 30, base = () => window.devicePixelRatio || 1 } = {}) {
    this.renderer = renderer;
    this.budget = budgetMs;
    this.base = base;
    this.level = 0;          // index in kScales
    this.pins = 0;           // how many ask for full size now
    this.fps = null;         // the last window's frames per second
    this.changes = 0;        // steps taken, for tests and curious users
    this.windowStart = null;
    this.windowFrames = 0;
    this.last = null;
    this.roomy = 0;          // windows in a row with room
    this.wait = new Array(kScales.length).fill(4000);   // ms before retrying a step up
    this.blockedUntil = new Array(kScales.length).fill(0);
    this.raisedAt = -Infinity;
    this.before = null;      // the level and mean frame time before the last step down
    this.gain = 0.85;        // a step down must make frames at least this much shorter
    this.hold = 10000;       // ms without stepping down after a step that did not help
    this.holdUntil = 0;
    this.onchange = null;
  }

  get scale() { return this.pins > 0 ? 1 : kScales[this.level]; }
  get pinned() { return this.pins > 0; }

  // the pixel ratio to draw with now
  pixelRatio() { return this.base() * this.scale; }

  // full size until the function returned is called (each call once)
  pin() {
    this.pins++;
    this.restart();
    this.changed();
    let done = false;
    return () => {
      if (done) return;
      done = true;
      this.pins--;
      this.restart();
      this.changed();
    };
  }

  restart() {
    this.windowStart = null;
    this.last = null;
    this.roomy = 0;
  }

  changed() {
    if (this.onchange) this.onchange(this.scale);
  }

  // called at an animation frame that drew nothing, with its timestamp (ms)
  idle(now) {
    if (this.last !== null && now - this.last > 1000) this.restart();   // a hidden tab, a stall
    else if (this.windowStart !== null && this.last !== null) this.windowStart += now - this.last;
    this.last = now;
  }

  // called at every animation frame that draws, with its timestamp (ms); true when the scale
  // changed
  frame(now) {
    if (this.last !== null && now - this.last > 1000) this.restart();   // a hidden tab, a stall
    this.last = now;
    if (this.windowStart === null) {
      this.windowStart = now;
      this.windowFrames = 0;
      return false;
    }
    this.windowFrames++;
    const span = now - this.windowStart;
    if (span < 500 || this.windowFrames < 8) return false;
    const mean = span / this.windowFrames;
    this.fps = 1000 / mean;
    this.windowStart = now;
    this.windowFrames = 0;
    if (this.pinned) return false;
    const before = this.before;
    this.before = null;
    if (before && before.level === this.level - 1 && mean > this.budget && mean > this.gain * before.mean) {
      // fewer pixels did not make the frames faster: pixels are not what is slow (a busy
      // machine, the page's other work). Back to the resolution before, and no lower for a
      // while (10 s, then twice as long each time, up to a minute)
      this.level = before.level;
      this.holdUntil = now + this.hold;
      this.hold = Math.min(this.hold * 2, 60000);
      this.changes++;
      this.changed();
      return true;
    }
    if (mean > this.budget && this.level < kScales.length - 1 && now >= this.holdUntil) {
      this.before = { level: this.level, mean };
      // a step up to this level that did not hold: wait longer before the next try
      if (now - this.raisedAt < 3000) this.wait[this.level] = Math.min(this.wait[this.level] * 2, 60000);
      this.blockedUntil[this.level] = now + this.wait[this.level];
      this.level++;
      this.roomy = 0;
      this.changes++;
      this.changed();
      return true;
    }
    if (mean < 0.6 * this.budget && this.level > 0) {
      this.roomy++;
      if (this.roomy >= 2 && now >= this.blockedUntil[this.level - 1]) {
        this.level--;
        this.raisedAt = now;
        this.roomy = 0;
        this.changes++;
        this.changed();
        return true;
      }
    } else {
      this.roomy = 0;
    }
    return false;
  }
}

// How often the view may be drawn (docs/viewer.md, "Drawing many bodies fast"). The simulation
// comes first: while it runs slower than its speed asks (behind()), and for `hold` ms after it
// was last seen so, the view is drawn at most `rate` times a second (a budget that grows by
// `rate` drawings a second, up to two, so a 60 Hz screen draws 36 a second, not 30), which
// leaves the CPU time of the other drawings to the simulation where the browser and gaitlab
// share a machine. Otherwise, and while pinned (a screenshot, a recording, "Full quality"), at
// every animation frame.
export class DrawingRate {
  constructor({ rate = 36, hold = 5000 } = {}) {
    this.rate = rate;
    this.hold = hold;
    this.budget = 1;                // drawings allowed now while yielding
    this.until = -Infinity;         // yielding until this time (ms)
    this.last = null;               // the last animation frame's time
    this.yielding = false;
  }

  // whether a frame's state says the simulation runs slower than asked: playing, at a finite
  // speed without a delay, its measured real-time factor below 95 % of that speed
  static behind(state) {
    return Boolean(state && state.playing && !state.delay && typeof state.speed === 'number' &&
      typeof state.measured === 'number' && state.measured < 0.95 * state.speed);
  }

  // at an animation frame (its timestamp, ms): whether the view may be drawn in it
  allow(now, behind, pinned) {
    if (behind) this.until = now + this.hold;
    this.yielding = now < this.until && !pinned;
    if (this.last !== null) {
      this.budget = Math.min(2, this.budget + ((now - this.last) * this.rate) / 1000);
    }
    this.last = now;
    return !this.yielding || this.budget >= 1;
  }

  // the view was drawn in the frame allow() was last asked about
  drew() {
    if (this.yielding) this.budget -= 1;
  }
}
