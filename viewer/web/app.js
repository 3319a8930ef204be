// The gaitlab viewer page: a 3D view of the simulation gaitlab serves, its controls and the
// controllers' parameters. The scene comes once (and again when it changes), then frames of
// poses, over one server-sent event stream (/api/events); commands go back as JSON posts
// (/api/command). docs/viewer.md describes the protocol.
import { createView } from './scene.js';
import uPlot from 'uplot';
import { csvText, download, plotBox, plotPng } from './plotexport.js';

const token = new URLSearchParams(location.search).get('token');
const query = token ? `?token=${encodeURIComponent(token)}` : '';
// an API address with its parameters (and the token, when there is one)
function api(path, params = {}) {
  const p = new URLSearchParams(params);
  if (token) p.set('token', token);
  const q = p.toString();
  return q ? `${path}?${q}` : path;
}

// what tests (and curious users, from the browser console) can read
const gaitlab = {
  scene: null,      // the scene as gaitlab sent it
  frame: null,      // the latest frame
  frames: 0,        // frames received
  drawn: 0,         // frames drawn
  drawnTime: null,  // the simulated time of the last frame drawn, s
  drawings: 0,      // drawings of the 3D view (it draws only when something changed)
  messages: [],     // {level, text}
  errors: [],       // command errors
  connected: false,
  plots: [],        // the live plots: { names, paused, points() }
};
window.gaitlab = gaitlab;

const $ = (id) => document.getElementById(id);
const canvas = $('scene');

// ---------------------------------------------------------------------------------------------
// the 3D view (scene.js): bodies, objects, camera, picking, adaptive resolution

const view = createView(gaitlab, canvas, { follow: $('follow'), status: $('drawing') });
gaitlab.three = view;
gaitlab.picked = null;   // the body or object clicked last: { kind, name, ... }
view.onpick = (p) => { $('picked').textContent = p ? `${p.robot ? `${p.robot} ` : ''}${p.name}` : ''; };
let unpin = null;
$('full-quality').addEventListener('change', (e) => {
  if (e.target.checked && !unpin) unpin = view.pin();
  if (!e.target.checked && unpin) { unpin(); unpin = null; }
});

function buildScene(scene) {
  view.build(scene);
  $('sim-name').textContent = `simulation ${scene.simulation}`;
  buildParams(scene);
  buildSensors(scene);
}

// ---------------------------------------------------------------------------------------------
// commands

function message(level, text) {
  gaitlab.messages.push({ level, text });
  const box = $('messages');
  const line = document.createElement('div');
  line.className = level;
  line.textContent = text;
  box.appendChild(line);
  while (box.childNodes.length > 300) box.removeChild(box.firstChild);
  box.scrollTop = box.scrollHeight;
}

async function send(command) {
  if (gaitlab.scene && command.simulation === undefined) command.simulation = gaitlab.scene.simulation;
  try {
    const r = await fetch(`api/command${query}`, {
      method: 'POST',
      headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify(command),
    });
    if (!r.ok) {
      const body = await r.json().catch(() => ({ error: `HTTP ${r.status}` }));
      gaitlab.errors.push(body.error);
      message('error', `${command.command}: ${body.error}`);
    }
  } catch (e) {
    message('error', `${command.command}: gaitlab does not answer (${e.message})`);
  }
}

$('play').addEventListener('click', () => {
  const state = gaitlab.frame ? gaitlab.frame.state : {};
  send({ command: state.playing ? 'pause' : 'play' });
});
$('step').addEventListener('click', () =>
  send({ command: 'step', ticks: gaitlab.scene ? gaitlab.scene.control_every : 1 }));
$('reset').addEventListener('click', () => send({ command: 'reset' }));
$('speed').addEventListener('change', (e) => {
  const v = e.target.value;
  send({ command: 'speed', value: v === 'max' ? 'max' : Number(v) });
});
$('delay').addEventListener('change', (e) => {
  send({ command: 'delay', value: Number(e.target.value) / 1000 });
});
$('home').addEventListener('click', () => { $('follow').checked = false; view.viewAll(); });
document.addEventListener('keydown', (e) => {
  if (e.target.tagName === 'INPUT' || e.target.tagName === 'SELECT') return;
  if (e.key === ' ') { e.preventDefault(); $('play').click(); }
  if (e.key === 's') $('step').click();
  if (e.key === 'r') $('reset').click();
});

// ---------------------------------------------------------------------------------------------
// the simulations of the script: the page shows (and its controls, sliders and plots address)
// the one chosen here; the list comes from the server as the event `simulations`

function showSimulations(list) {
  gaitlab.simulations = list;
  const select = $('simulation');
  select.textContent = '';
  for (const s of list.simulations) {
    const o = document.createElement('option');
    o.value = s.simulation;
    const robots = s.robots.length > 0 ? s.robots.join(', ') : 'no robot';
    const ctls = s.controllers.length > 0 ? ` (${s.controllers.join(', ')})` : '';
    o.textContent = `${s.simulation}: ${robots}${ctls}`;
    o.selected = s.shown;
    select.appendChild(o);
  }
  $('simulations-row').hidden = list.simulations.length < 2;
  $('simulation-follow').textContent = list.chosen ? '' : '(the newest)';
}
$('simulation').addEventListener('change', (e) =>
  send({ command: 'show', simulation: Number(e.target.value) }));

// ---------------------------------------------------------------------------------------------
// parameters: one slider each, with its range and unit

let sliders = [];   // in frame.params order: { input, output, param }
let dragging = null;

function format(v) {
  return Math.abs(v) >= 100 ? v.toFixed(1) : Math.abs(v) >= 1 ? v.toFixed(2) : v.toPrecision(3);
}

function buildParams(scene) {
  const box = $('params');
  box.textContent = '';
  sliders = [];
  if (scene.controllers.length === 0) {
    box.innerHTML = '<p class="small">no controller</p>';
    return;
  }
  for (const c of scene.controllers) {
    const h = document.createElement('h3');
    h.textContent = c.label === c.name ? `${c.label} (${c.robot})` : `${c.label}: ${c.name} (${c.robot})`;
    box.appendChild(h);
    for (const p of c.params) {
      const row = document.createElement('div');
      row.className = 'param';
      const id = `param-${c.label}-${p.name}`;
      const label = document.createElement('label');
      label.htmlFor = id;
      label.textContent = p.name;
      label.title = `${c.label}.${p.name}`;
      const input = document.createElement('input');
      input.type = 'range';
      input.id = id;
      input.min = p.min;
      input.max = p.max;
      // a power of ten, so round values (20 deg, 0.5 Hz) are on the slider
      input.step = p.max > p.min ? 10 ** Math.floor(Math.log10((p.max - p.min) / 1000)) : 1;
      input.value = p.default;
      input.dataset.controller = c.label;
      input.dataset.param = p.name;
      const output = document.createElement('output');
      output.htmlFor = id;
      output.textContent = `${format(p.default)} ${p.unit}`;
      const range = document.createElement('div');
      range.className = 'range';
      range.textContent = `${format(p.min)} … ${format(p.max)} ${p.unit}`;
      row.append(label, input, output, range);
      box.appendChild(row);
      const slider = { input, output, param: p, controller: c.label, sent: 0, value: null };
      sliders.push(slider);
      // a slider's commands go to the simulation its scene belongs to, even when another one is
      // shown by the time they are sent; a value is sent once (the change after the last input
      // event of a drag repeats it, and could arrive after the page showed another simulation)
      const set = (value) => {
        slider.value = value;
        send({ command: 'param', controller: c.label, name: p.name, value, simulation: scene.simulation });
      };
      // while dragging: a few commands a second; the last value always goes
      input.addEventListener('input', () => {
        dragging = slider;
        output.textContent = `${format(Number(input.value))} ${p.unit}`;
        const now = performance.now();
        if (now - slider.sent > 60) {
          slider.sent = now;
          set(Number(input.value));
        }
      });
      input.addEventListener('change', () => {
        if (Number(input.value) !== slider.value) set(Number(input.value));
        dragging = null;
      });
    }
  }
}

// sensors: a switch each; a switch is an event of the run (origin viewer), like a parameter
let sensorBoxes = [];
function buildSensors(scene) {
  const box = $('sensors');
  box.textContent = '';
  sensorBoxes = [];
  if (!scene.sensors || scene.sensors.length === 0) {
    box.innerHTML = '<p class="small">no sensor</p>';
    return;
  }
  for (const s of scene.sensors) {
    const label = document.createElement('label');
    label.className = 'pick';
    const input = document.createElement('input');
    input.type = 'checkbox';
    input.dataset.sensor = s.name;
    input.checked = true;
    input.addEventListener('change', () =>
      send({ command: 'sensor', name: s.name, enabled: input.checked }));
    label.append(input, ` ${s.name} (${s.kind})`);
    const line = document.createElement('div');
    line.appendChild(label);
    box.appendChild(line);
    sensorBoxes.push(input);
  }
}

// a text or an input's value written only when it changes: every write makes the browser lay
// out and paint the page again, and frames come up to 60 times a second (with 40 robots, the
// sliders' 120 labels rewritten at every frame cost more than drawing the 3D view)
function setText(el, text) {
  if (el.textContent !== text) el.textContent = text;
}

function showFrame(f) {
  setText($('time'), f.time.toFixed(3));
  const s = f.state || {};
  setText($('play'), s.playing ? 'Pause' : 'Play');
  let state = '';
  if (s.failure) state = s.failure;
  else if (s.console && s.finished) state = s.playing ? '(playing)' : '(paused: the console has it)';
  else if (s.console) state = '(the console runs it)';
  else if (s.finished) state = s.playing ? '(script finished, playing on)' : '(script finished)';
  else if (!s.running && !s.held) state = '(waiting for the script)';
  else if (s.held) state = '(paused)';
  setText($('state'), state);
  const speed = s.speed === 'max' ? 'as fast as possible' : `${s.speed}×`;
  setText($('measured'), `target ${speed}` +
    (s.measured !== null && s.measured !== undefined ? `, measured ${s.measured.toFixed(2)}× real time` : ''));
  if (s.delay !== undefined && document.activeElement !== $('delay')) {
    const delay = Math.round(s.delay * 1e6) / 1e3;
    if (Number($('delay').value) !== delay || $('delay').value === '') $('delay').value = delay;
  }
  if (s.sensors && s.sensors.length === sensorBoxes.length) {
    s.sensors.forEach((on, i) => { if (sensorBoxes[i].checked !== on) sensorBoxes[i].checked = on; });
  }
  if (f.params.length === sliders.length) {
    f.params.forEach((v, i) => {
      const sl = sliders[i];
      if (sl === dragging || v === null) return;
      if (Number(sl.input.value) !== v) {
        sl.input.value = v;
        sl.value = null;   // the engine's value now: the next change is sent whatever it is
      }
      setText(sl.output, `${format(v)} ${sl.param.unit}`);
    });
  }
}

// ---------------------------------------------------------------------------------------------
// the stream

function connect() {
  const events = new EventSource(`api/events${query}`);
  events.addEventListener('open', () => {
    gaitlab.connected = true;
    $('connection').hidden = true;
  });
  events.addEventListener('error', () => {
    gaitlab.connected = false;
    $('connection').hidden = false;
    $('connection').textContent = 'gaitlab does not answer: is it still running? (retrying)';
  });
  events.addEventListener('scene', (e) => {
    const before = gaitlab.scene;
    gaitlab.scene = JSON.parse(e.data);
    buildScene(gaitlab.scene);
    // the first scene, or another simulation chosen: look at it all
    if (before === null || before.simulation !== gaitlab.scene.simulation) view.viewAllSoon();
    loadSeries();
  });
  events.addEventListener('frame', (e) => {
    const f = JSON.parse(e.data);
    gaitlab.frame = f;
    gaitlab.frames++;
    showFrame(f);
  });
  events.addEventListener('simulations', (e) => showSimulations(JSON.parse(e.data)));
  events.addEventListener('message', (e) => {
    const m = JSON.parse(e.data);
    message(m.level, m.text);
  });
}

// ---------------------------------------------------------------------------------------------
// live plots (uPlot): the series of the simulation's live buffers, chosen by checkboxes

let seriesInfo = null;          // { simulation, series: [...], sample_every, refresh, size }
const store = { time: [], values: new Map(), since: null, names: '' };
let plotCount = 0;

async function loadSeries() {
  const sim = gaitlab.scene ? gaitlab.scene.simulation : 0;
  try {
    const r = await fetch(api('api/live/series', { simulation: sim }));
    if (!r.ok) return;
    seriesInfo = await r.json();
  } catch (e) {
    return;
  }
  $('live-every').value = seriesInfo.sample_every;
  $('live-refresh').value = seriesInfo.refresh;
  $('live-size').value = seriesInfo.size;
  const known = new Set(seriesInfo.series.map((s) => s.name));
  const current = seriesShown();
  for (const p of gaitlab.plots) {
    for (const n of [...p.names]) if (!known.has(n)) p.names.delete(n);
    // a plot added before the shown simulation's series were known starts with its default now
    if (current && p.wantsDefault) {
      p.wantsDefault = false;
      const d = defaultSeries();
      if (d && p.names.size === 0) p.names.add(d);
    }
    p.buildPicker();
    p.rebuild();
  }
  store.since = null;   // everything again, for the new simulation
}

// whether the series known are those of the simulation shown (another one chosen, its series
// arrive a moment later)
function seriesShown() {
  return Boolean(seriesInfo && gaitlab.scene && seriesInfo.simulation === gaitlab.scene.simulation);
}

// a new plot's series: the first robot's centre of mass, or the first series
function defaultSeries() {
  const first = seriesInfo.series.find((s) => /\.com\.x$/.test(s.name)) || seriesInfo.series[0];
  return first ? first.name : null;
}

for (const [id, field] of [['live-every', 'sample_every'], ['live-refresh', 'refresh'], ['live-size', 'size']]) {
  $(id).addEventListener('change', (e) => {
    const v = Number(e.target.value);
    send({ command: 'live', [field]: field === 'refresh' ? v : Math.round(v) });
  });
}

// the checkboxes of one plot, grouped by kind, then robot / controller, then quantity (joints
// side by side)
function picker(plot) {
  const root = document.createElement('details');
  const summary = document.createElement('summary');
  summary.textContent = 'series…';
  root.appendChild(summary);
  if (!seriesInfo) return root;
  const groups = new Map();
  for (const s of seriesInfo.series) {
    const key = `${s.kind}|${s.source}`;
    if (!groups.has(key)) groups.set(key, new Map());
    const q = groups.get(key);
    const value = s.body ? `${s.body}.${s.value}` : s.value;
    if (!q.has(value)) q.set(value, []);
    q.get(value).push(s);
  }
  for (const [key, quantities] of groups) {
    const [kind, source] = key.split('|');
    const d = document.createElement('details');
    const sm = document.createElement('summary');
    sm.textContent = `${kind} ${source}`;
    d.appendChild(sm);
    for (const [value, list] of quantities) {
      const line = document.createElement('div');
      const unit = list[0].unit ? ` (${list[0].unit})` : '';
      line.append(`${value}${unit}: `);
      for (const s of list) {
        const label = document.createElement('label');
        label.className = 'pick';
        const box = document.createElement('input');
        box.type = 'checkbox';
        box.dataset.series = s.name;
        box.checked = plot.names.has(s.name);
        box.addEventListener('change', () => {
          if (box.checked) plot.names.add(s.name); else plot.names.delete(s.name);
          plot.rebuild();
          store.since = null;
        });
        label.append(box, s.joint ? `${s.joint}` : '✓');
        line.appendChild(label);
      }
      d.appendChild(line);
    }
    root.appendChild(d);
  }
  return root;
}

function addPlot(names = []) {
  const id = ++plotCount;
  const pause = document.createElement('button');
  pause.textContent = 'Pause';
  pause.title = 'Freeze this plot (the others go on)';
  const { el, png, csv, close, pickHolder, chart } = plotBox({
    id: `plot-${id}`, className: 'plot', title: `plot ${id}`, buttons: [pause],
    hint: 'drag across the plot to zoom (it pauses), double-click to zoom out' });
  $('plots').appendChild(el);

  const plot = {
    id, el, names: new Set(names), paused: false, u: null,
    points: () => (plot.u ? plot.u.data[0].length : 0),
    buildPicker() {
      pickHolder.textContent = '';
      pickHolder.appendChild(picker(plot));
    },
    rebuild() {
      if (plot.u) plot.u.destroy();
      plot.u = null;
      const names = [...plot.names];
      if (names.length === 0) return;
      const units = names.map((n) => {
        const s = seriesInfo && seriesInfo.series.find((x) => x.name === n);
        return s && s.unit ? s.unit : '';
      });
      // one scale per unit: metres and degrees do not share an axis (left, then right)
      const scaleOf = (u) => u || 'value';
      const scaleNames = [...new Set(units.map(scaleOf))];
      const colours = ['#e07b24', '#2a7fbf', '#3f9e4d', '#9b4fb3', '#c33', '#8a6d3b', '#17a2b8', '#555'];
      const axes = [{ label: 't (s)' }];
      scaleNames.slice(0, 2).forEach((sc, i) => axes.push({
        scale: sc, side: i === 0 ? 3 : 1, label: sc === 'value' ? '' : sc,
        grid: { show: i === 0 },
      }));
      const scales = { x: { time: false } };
      for (const sc of scaleNames) scales[sc] = {};
      plot.u = new uPlot({
        width: 426, height: 170,
        scales,
        axes,
        legend: { live: true },
        series: [{ label: 't' }, ...names.map((n, i) => ({
          label: units[i] ? `${n} (${units[i]})` : n, scale: scaleOf(units[i]),
          stroke: colours[i % colours.length], width: 1.5,
        }))],
        hooks: {
          // a zoom by the user freezes the plot, so new data does not undo it
          setSelect: [(u) => { if (u.select.width > 0) { plot.paused = true; pause.textContent = 'Play'; } }],
        },
      }, plot.data(), chart);
      plot.u.over.addEventListener('dblclick', () => {
        plot.paused = false;
        pause.textContent = 'Pause';
      });
    },
    data() {
      // a series just chosen has no samples until the next fetch: nulls, as long as the time
      const n = store.time.length;
      return [store.time.slice(), ...[...plot.names].map((name) => {
        const v = store.values.get(name) || [];
        return v.length === n ? v.slice() : new Array(n - v.length).fill(null).concat(v);
      })];
    },
    update() {
      if (plot.u && !plot.paused) plot.u.setData(plot.data());
    },
    // the file name of an export: the simulation, the plot and the time shown last
    exportName(ext) {
      const sim = gaitlab.scene ? gaitlab.scene.name || `simulation${gaitlab.scene.simulation}` : 'simulation';
      const t = plot.u && plot.u.data[0].length > 0 ? plot.u.data[0][plot.u.data[0].length - 1] : 0;
      return `${sim}-plot${id}-t${t.toFixed(3)}.${ext}`;
    },
    // what is drawn (a paused plot: what it froze), as a PNG and as CSV; false when nothing is
    exportable() {
      if (plot.u && plot.u.data[0].length > 0) return true;
      message('error', `plot ${id}: nothing to export yet (${plot.names.size === 0
        ? 'choose a series first' : 'no samples yet'})`);
      return false;
    },
    png() {
      if (!plot.exportable()) return Promise.resolve(null);
      const sim = gaitlab.scene ? gaitlab.scene.name || `simulation ${gaitlab.scene.simulation}` : '';
      return plotPng(plot.u, `${sim} (live plot ${id})`, plot.exportName('png'));
    },
    csv() {
      if (!plot.exportable()) return null;
      const text = csvText([...plot.names], plot.u.data);
      download(new Blob([text], { type: 'text/csv' }), plot.exportName('csv'));
      return text;
    },
  };
  png.addEventListener('click', () => plot.png());
  csv.addEventListener('click', () => plot.csv());
  pause.addEventListener('click', () => {
    plot.paused = !plot.paused;
    pause.textContent = plot.paused ? 'Play' : 'Pause';
    if (!plot.paused) plot.update();
  });
  close.addEventListener('click', () => {
    if (plot.u) plot.u.destroy();
    el.remove();
    gaitlab.plots.splice(gaitlab.plots.indexOf(plot), 1);
  });
  plot.buildPicker();
  plot.rebuild();
  gaitlab.plots.push(plot);
  return plot;
}
$('add-plot').addEventListener('click', () => {
  // not the series of a simulation shown before: if the shown one's have not arrived yet, the
  // plot takes its default when they do
  const shown = seriesShown();
  const first = shown ? defaultSeries() : null;
  const p = addPlot(first ? [first] : []);
  p.wantsDefault = !shown;
  p.el.querySelector('details').open = true;
  store.since = null;
});

// the samples of every plotted series, fetched since the last one seen
async function pollLive() {
  const wanted = [...new Set(gaitlab.plots.flatMap((p) => [...p.names]))].sort();
  const refresh = seriesInfo ? Math.max(seriesInfo.refresh, 0.05) : 0.2;
  if (wanted.length > 0 && gaitlab.scene) {
    const key = wanted.join(',');
    if (key !== store.names) store.since = null;
    try {
      const params = { simulation: gaitlab.scene.simulation, series: key };
      if (store.since !== null) params.since = store.since;
      const r = await fetch(api('api/live', params));
      if (r.ok) {
        const d = await r.json();
        if (store.since === null || d.restart || key !== store.names) {
          store.time = [];
          store.values = new Map(wanted.map((n) => [n, []]));
        }
        store.names = key;
        store.time.push(...d.time);
        d.names.forEach((n, i) => store.values.get(n).push(...d.values[i]));
        const size = Number($('live-size').value) || 2000;
        if (store.time.length > size) {
          const cut = store.time.length - size;
          store.time.splice(0, cut);
          for (const v of store.values.values()) v.splice(0, cut);
        }
        if (store.time.length > 0) store.since = store.time[store.time.length - 1];
        for (const p of gaitlab.plots) p.update();
      }
    } catch (e) {
      // gaitlab went away: the stream's handler says so
    }
  }
  setTimeout(pollLive, refresh * 1000);
}

connect();
pollLive();
