// Recorded runs, pictures and video on the viewer's page (docs/viewer.md).
// - Always: a PNG screenshot of the 3D view and a WebM recording of it (MediaRecorder on the
//   canvas), as downloads.
// - With a recorded run (`gaitlab view RUN`, /api/run answers): a timeline to scrub (the
//   server plays the recorded poses back: the ordinary play, pause, step and speed controls
//   and the `seek` command), plots of recorded series chosen by checkboxes (grouped as the
//   live plots are) with PNG and CSV export, and a picker of other run folders.
// - With ?video=1 (what `gaitlab view RUN --video OUT.webm` opens in headless chromium): plays
//   the run from its start while recording the 3D view, and posts the WebM back.
// app.js draws the scene and frames; this module only reads window.gaitlab.
import uPlot from 'uplot';
import { download, plotBox, plotPng } from './plotexport.js';

const params = new URLSearchParams(location.search);
const token = params.get('token');
function api(path, extra = {}) {
  const p = new URLSearchParams(extra);
  if (token) p.set('token', token);
  const q = p.toString();
  return q ? `${path}?${q}` : path;
}
const $ = (id) => document.getElementById(id);
const canvas = $('scene');
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

const replay = {
  info: null,        // GET /api/run: the run and its series
  plots: [],         // recorded plots: { names, data, u }
  recording: false,  // a WebM recording of the view runs
  errors: [],
  video: null,       // in video mode: 'recording', 'sending', 'sent' or an error
};

function say(level, text) {
  const box = $('messages');
  const line = document.createElement('div');
  line.className = level;
  line.textContent = text;
  box.appendChild(line);
  box.scrollTop = box.scrollHeight;
  if (level === 'error') replay.errors.push(text);
}

async function post(path, body, type = 'application/json') {
  const r = await fetch(api(path), {
    method: 'POST',
    headers: { 'Content-Type': type },
    body: type === 'application/json' ? JSON.stringify(body) : body,
  });
  if (!r.ok) {
    const b = await r.json().catch(() => ({ error: `HTTP ${r.status}` }));
    throw new Error(b.error);
  }
  return r.json();
}

function stamp() {
  const f = window.gaitlab && window.gaitlab.frame;
  return f ? `t${f.time.toFixed(3)}` : 'view';
}

// ---------------------------------------------------------------------------------------------
// pictures and video of the 3D view (live or recorded)

// the 3D view at its full size, whatever resolution it draws with to keep up (scene.js)
const three = () => window.gaitlab.three;

function screenshot() {
  const release = three().pin();
  three().render();
  return new Promise((resolve) => canvas.toBlob((b) => {
    download(b, `gaitlab-${stamp()}.png`);
    resolve(b);
  }, 'image/png')).finally(release);
}

function webmType() {
  // VP8 first: it costs the browser less than VP9 while it draws
  for (const t of ['video/webm;codecs=vp8', 'video/webm;codecs=vp9', 'video/webm']) {
    if (window.MediaRecorder && MediaRecorder.isTypeSupported(t)) return t;
  }
  return null;
}

// records the canvas until stop() is called; resolves with the WebM blob
function recordCanvas() {
  const type = webmType();
  if (!type) throw new Error('this browser cannot record WebM video (MediaRecorder)');
  const stream = canvas.captureStream(30);
  const rec = new MediaRecorder(stream, { mimeType: type, videoBitsPerSecond: 4e6 });
  const chunks = [];
  rec.ondataavailable = (e) => { if (e.data.size > 0) chunks.push(e.data); };
  const done = new Promise((resolve, reject) => {
    rec.onstop = () => {
      release();
      stream.getTracks().forEach((t) => t.stop());
      resolve(new Blob(chunks, { type: 'video/webm' }));
    };
    rec.onerror = (e) => {
      release();
      reject(new Error(e.error ? e.error.message : 'recording failed'));
    };
  });
  // recorded at the full size (pinned until it stops), and drawn at every animation frame so
  // the video has a steady frame rate even while nothing moves (scene.js draws only changes)
  const release = three().pin();
  let recording = true;
  const keepDrawing = () => {
    if (!recording) return;
    three().invalidate();
    requestAnimationFrame(keepDrawing);
  };
  requestAnimationFrame(keepDrawing);
  rec.addEventListener('stop', () => { recording = false; });
  rec.addEventListener('error', () => { recording = false; });
  rec.start(1000);
  return { stop: () => { rec.stop(); return done; } };
}

function captureButtons() {
  const row = document.createElement('div');
  row.className = 'row';
  row.id = 'capture';
  const shot = document.createElement('button');
  shot.id = 'screenshot';
  shot.textContent = 'Screenshot';
  shot.title = 'Download the 3D view as a PNG picture';
  shot.addEventListener('click', () => screenshot());
  const rec = document.createElement('button');
  rec.id = 'record-video';
  rec.textContent = 'Record video';
  rec.title = 'Record the 3D view as a WebM video (click again to stop and download it)';
  let running = null;
  rec.addEventListener('click', async () => {
    if (running) {
      const r = running;
      running = null;
      rec.textContent = 'Record video';
      replay.recording = false;
      download(await r.stop(), `gaitlab-${stamp()}.webm`);
      return;
    }
    try {
      running = recordCanvas();
      replay.recording = true;
      rec.textContent = '■ Stop recording';
    } catch (e) {
      say('error', e.message);
    }
  });
  row.append(shot, rec);
  $('controls').appendChild(row);
}

// ---------------------------------------------------------------------------------------------
// a recorded run: timeline, picker, plots

let dragging = false;
let seekBusy = false;
let seekWanted = null;

async function seek(t) {
  seekWanted = t;
  if (seekBusy) return;
  seekBusy = true;
  while (seekWanted !== null) {
    const time = seekWanted;
    seekWanted = null;
    try {
      await post('api/command', { command: 'seek', time });
    } catch (e) {
      say('error', `seek: ${e.message}`);
    }
  }
  seekBusy = false;
}

function buildTimeline(holder) {
  const row = document.createElement('div');
  row.className = 'row timeline';
  const slider = document.createElement('input');
  slider.type = 'range';
  slider.id = 'timeline';
  slider.title = 'Drag to go to a time of the run';
  const label = document.createElement('span');
  label.id = 'timeline-time';
  label.className = 'small';
  slider.addEventListener('input', () => {
    dragging = true;
    seek(Number(slider.value));
  });
  slider.addEventListener('change', () => { dragging = false; });
  row.append(slider, label);
  holder.appendChild(row);
  const update = () => {
    const i = replay.info;
    const f = window.gaitlab && window.gaitlab.frame;
    if (i) {
      slider.min = i.start;
      slider.max = i.end;
      slider.step = 'any';
      if (f && !dragging) slider.value = f.time;
      label.textContent = `${(f ? f.time : i.start).toFixed(3)} / ${i.end.toFixed(3)} s`;
      $('sim-name').textContent = `run ${i.name}`;
    }
    setTimeout(update, 50);
  };
  update();
}

async function buildPicker(holder) {
  const row = document.createElement('div');
  row.className = 'row';
  const select = document.createElement('select');
  select.id = 'run-picker';
  select.title = 'Run folders below the folder gaitlab runs in, or beside this run';
  const open = document.createElement('button');
  open.id = 'run-open';
  open.textContent = 'Open';
  const refresh = async () => {
    try {
      const r = await fetch(api('api/run/list'));
      const l = await r.json();
      select.textContent = '';
      for (const p of l.runs) {
        const o = document.createElement('option');
        o.value = p;
        o.textContent = p;
        o.selected = p === l.current;
        select.appendChild(o);
      }
    } catch (e) {
      // gaitlab went away: app.js says so
    }
  };
  select.addEventListener('focus', refresh);
  open.addEventListener('click', async () => {
    open.disabled = true;
    try {
      await post('api/run/open', { path: select.value });
      await loadRun();
    } catch (e) {
      say('error', `open ${select.value}: ${e.message}`);
    } finally {
      open.disabled = false;
    }
  });
  row.append('run folder', select, open);
  holder.appendChild(row);
  await refresh();
}

// the checkboxes of a plot: kind and source, then quantity, a box per joint
function seriesPicker(plot) {
  const root = document.createElement('details');
  const summary = document.createElement('summary');
  summary.textContent = 'series…';
  root.appendChild(summary);
  const groups = new Map();
  for (const s of replay.info.series) {
    const key = `${s.kind} ${s.source}`;
    if (!groups.has(key)) groups.set(key, new Map());
    const q = groups.get(key);
    const value = s.body ? `${s.body}.${s.value}` : s.value;
    if (!q.has(value)) q.set(value, []);
    q.get(value).push(s);
  }
  for (const [key, quantities] of groups) {
    const d = document.createElement('details');
    const sm = document.createElement('summary');
    sm.textContent = key;
    d.appendChild(sm);
    for (const [value, list] of quantities) {
      const line = document.createElement('div');
      line.append(`${value}${list[0].unit ? ` (${list[0].unit})` : ''}: `);
      for (const s of list) {
        const label = document.createElement('label');
        label.className = 'pick';
        const box = document.createElement('input');
        box.type = 'checkbox';
        box.dataset.series = s.name;
        box.checked = plot.names.includes(s.name);
        box.addEventListener('change', () => {
          plot.names = plot.names.filter((n) => n !== s.name);
          if (box.checked) plot.names.push(s.name);
          plot.load();
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

const colours = ['#e07b24', '#2a7fbf', '#3f9e4d', '#9b4fb3', '#c33', '#8a6d3b', '#17a2b8', '#555'];
let plotCount = 0;

function addRecordedPlot(names) {
  const id = ++plotCount;
  const { el, png, csv, close, pickHolder, chart } = plotBox({
    id: `recorded-plot-${id}`, className: 'plot recorded', title: `recorded plot ${id}`,
    hint: 'drag across to zoom, double-click to zoom out; click to go to that time' });
  $('plots').prepend(el);

  const plot = {
    id, el, names: [...names], data: null, u: null,
    points: () => (plot.data ? plot.data[0].length : 0),
    async load() {
      if (plot.u) plot.u.destroy();
      plot.u = null;
      plot.data = null;
      if (plot.names.length === 0) return;
      const r = await fetch(api('api/run/data', { series: plot.names.join(',') }));
      const d = await r.json();
      if (!r.ok) {
        say('error', `plot: ${d.error}`);
        return;
      }
      plot.data = [d.time, ...d.values];
      const info = (n) => replay.info.series.find((s) => s.name === n) || {};
      const units = plot.names.map((n) => info(n).unit || '');
      const scaleOf = (u) => u || 'value';
      const scaleNames = [...new Set(units.map(scaleOf))];
      const axes = [{ label: 't (s)' }];
      scaleNames.slice(0, 2).forEach((sc, i) => axes.push({
        scale: sc, side: i === 0 ? 3 : 1, label: sc === 'value' ? '' : sc, grid: { show: i === 0 },
      }));
      const scales = { x: { time: false } };
      for (const sc of scaleNames) scales[sc] = {};
      plot.u = new uPlot({
        width: 426, height: 170, scales, axes,
        series: [{ label: 't' }, ...plot.names.map((n, i) => ({
          label: units[i] ? `${n} (${units[i]})` : n, scale: scaleOf(units[i]),
          stroke: colours[i % colours.length], width: 1.5,
        }))],
        hooks: {
          // where the timeline stands
          draw: [(u) => {
            const f = window.gaitlab && window.gaitlab.frame;
            if (!f) return;
            const x = u.valToPos(f.time, 'x', true);
            const { ctx } = u;
            ctx.save();
            ctx.strokeStyle = '#b00020';
            ctx.lineWidth = 1;
            ctx.beginPath();
            ctx.moveTo(x, u.bbox.top);
            ctx.lineTo(x, u.bbox.top + u.bbox.height);
            ctx.stroke();
            ctx.restore();
          }],
        },
      }, plot.data, chart);
      plot.u.over.addEventListener('click', () => {
        const l = plot.u.cursor.left;
        if (l >= 0 && plot.u.select.width === 0) seek(plot.u.posToVal(l, 'x'));
      });
    },
    // the plot as a picture: its canvas on white, the run's name and the legend
    png() {
      if (!plot.u) return Promise.resolve(null);
      return plotPng(plot.u, replay.info.name, `${replay.info.name}-plot${id}.png`);
    },
    csv() {
      if (plot.names.length === 0) return;
      const a = document.createElement('a');
      a.href = api('api/run/csv', { series: plot.names.join(',') });
      a.download = `${replay.info.name}-plot${id}.csv`;
      document.body.appendChild(a);
      a.click();
      a.remove();
    },
  };
  png.addEventListener('click', () => plot.png());
  csv.addEventListener('click', () => plot.csv());
  close.addEventListener('click', () => {
    if (plot.u) plot.u.destroy();
    el.remove();
    replay.plots.splice(replay.plots.indexOf(plot), 1);
  });
  pickHolder.appendChild(seriesPicker(plot));
  replay.plots.push(plot);
  plot.load();
  return plot;
}

async function loadRun() {
  const r = await fetch(api('api/run'));
  if (!r.ok) return false;
  const info = await r.json();
  if (!info.recorded) return false;  // a live simulation
  replay.info = info;
  if (!$('recorded-name')) return true;
  $('recorded-name').textContent = `${replay.info.name}: ${replay.info.state}, ` +
    `${replay.info.rows} rows`;
  // the plots of the run shown before go
  for (const p of [...replay.plots]) {
    if (p.u) p.u.destroy();
    p.el.remove();
  }
  replay.plots.length = 0;
  return true;
}

async function recordedMode() {
  document.body.classList.add('recorded');
  // a recorded run has no live series, sliders or sensor switches
  for (const sel of ['#plots-section > .row', '#params-section', '#sensors-section']) {
    const e = document.querySelector(sel);
    if (e) e.style.display = 'none';
  }
  const holder = document.createElement('div');
  holder.id = 'recorded';
  const name = document.createElement('div');
  name.id = 'recorded-name';
  name.className = 'small';
  holder.appendChild(name);
  buildTimeline(holder);
  const row = document.createElement('div');
  row.className = 'row';
  const add = document.createElement('button');
  add.id = 'add-recorded-plot';
  add.textContent = 'Add plot';
  add.title = 'A plot of recorded series you choose';
  add.addEventListener('click', () => {
    const s = replay.info.series;
    const first = s.find((x) => /\.com\.x$/.test(x.name)) || s[0];
    const p = addRecordedPlot(first ? [first.name] : []);
    p.el.querySelector('details').open = true;
  });
  row.appendChild(add);
  holder.appendChild(row);
  $('plots-section').prepend(holder);
  await buildPicker(row);
  // the timeline marker in the plots follows the frames
  setInterval(() => { for (const p of replay.plots) if (p.u) p.u.redraw(false, false); }, 200);
}

// ---------------------------------------------------------------------------------------------
// video mode: the run drawn frame by frame (seek, draw, encode), so the video keeps the run's
// time however slowly the browser draws; VP8 through WebCodecs, put in WebM by webm-muxer;
// the file is posted back in pieces

async function until(test, what, seconds = 30) {
  for (let i = 0; i < seconds * 100; ++i) {
    if (test()) return;
    await sleep(10);
  }
  throw new Error(`timed out waiting for ${what}`);
}

const animationFrame = () => new Promise((r) => requestAnimationFrame(r));

export const videoFps = 25;

async function videoMode() {
  const g = () => window.gaitlab;
  const speed = Number(params.get('speed')) || 1;
  try {
    replay.video = 'recording';
    three().pin();   // every frame at the requested size, however long it takes to draw
    await until(() => g().scene && g().frame && g().drawn > 0, 'the scene');
    if (!window.VideoEncoder) throw new Error('this browser has no VideoEncoder (WebCodecs)');
    const { Muxer, ArrayBufferTarget } = await import('./lib/webm-muxer.mjs');
    await sleep(300);  // the camera settles on the robot
    const width = canvas.width & ~1;
    const height = canvas.height & ~1;
    const muxer = new Muxer({
      target: new ArrayBufferTarget(),
      video: { codec: 'V_VP8', width, height, frameRate: videoFps },
    });
    let failure = null;
    const encoder = new VideoEncoder({
      output: (chunk, meta) => muxer.addVideoChunk(chunk, meta),
      error: (e) => { failure = e; },
    });
    encoder.configure({ codec: 'vp8', width, height, bitrate: 4e6, framerate: videoFps });
    const { start, end } = replay.info;
    const frames = Math.max(1, Math.round(((end - start) / speed) * videoFps)) + 1;
    for (let k = 0; k < frames; ++k) {
      const t = Math.min(end, start + (k * speed) / videoFps);
      await post('api/command', { command: 'seek', time: t });
      await until(() => g().frame.time === t, `the frame at ${t} s`);
      // app.js draws the latest frame at the next animation frame, before this module's
      // callback (it asked first)
      await animationFrame();
      const frame = new VideoFrame(canvas, {
        timestamp: Math.round((k * 1e6) / videoFps),
        duration: Math.round(1e6 / videoFps),
        visibleRect: { x: 0, y: 0, width, height },
      });
      encoder.encode(frame, { keyFrame: k % (2 * videoFps) === 0 });
      frame.close();
      if (failure) throw failure;
      replay.video = `frame ${k + 1} of ${frames}`;
      while (encoder.encodeQueueSize > 4) await sleep(5);
    }
    await encoder.flush();
    if (failure) throw failure;
    muxer.finalize();
    const bytes = muxer.target.buffer;
    replay.video = 'sending';
    const piece = 60000;  // the server takes at most 64 KiB a request
    for (let at = 0; at < bytes.byteLength; at += piece) {
      await post(`api/run/video?offset=${at}`, bytes.slice(at, at + piece), 'application/octet-stream');
    }
    await post('api/run/video/done', {});
    replay.video = 'sent';
  } catch (e) {
    replay.video = e.message || String(e);
    await post('api/run/video/done', { error: replay.video }).catch(() => {});
  }
}

// ---------------------------------------------------------------------------------------------

window.gaitlab.replay = replay;
replay.screenshot = screenshot;
replay.addPlot = (names) => addRecordedPlot(names);
replay.seek = seek;
captureButtons();
if (await loadRun()) {
  await recordedMode();
  await loadRun();
  if (params.get('video') === '1') {
    document.body.classList.add('video');
    // the video's size: the 3D view's, in pixels (?size=WxH, even numbers)
    const size = /^(\d+)x(\d+)$/.exec(params.get('size') || '960x540');
    if (size) {
      $('view').style.width = `${size[1]}px`;
      $('view').style.height = `${size[2]}px`;
    }
    videoMode();
  }
}
