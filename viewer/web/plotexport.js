// Exporting a plot of the viewer's page (docs/viewer.md), shared by the live plots (app.js) and
// the recorded ones (replay.js): the plot as a PNG picture (its canvas on white, a title and the
// legend) and its data as CSV (time, then one column per series), both as downloads.

// a file the browser downloads
export function download(blob, name) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = name;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10000);
}

// the uPlot u as a PNG picture titled `title`, downloaded as `name`; resolves to the blob
export function plotPng(u, title, name) {
  const src = u.ctx.canvas;
  const series = u.series.slice(1);
  const out = document.createElement('canvas');
  const dpr = src.width / u.width || 1;
  out.width = src.width;
  out.height = src.height + (28 + 18 * series.length) * dpr;
  const c = out.getContext('2d');
  c.fillStyle = '#fff';
  c.fillRect(0, 0, out.width, out.height);
  c.scale(dpr, dpr);
  c.fillStyle = '#1d2430';
  c.font = 'bold 13px sans-serif';
  c.fillText(title, 8, 18);
  c.drawImage(src, 0, 24, src.width / dpr, src.height / dpr);
  c.font = '12px sans-serif';
  series.forEach((s, i) => {
    const y = 24 + src.height / dpr + 16 + 18 * i;
    c.strokeStyle = s.stroke();
    c.lineWidth = 2;
    c.beginPath();
    c.moveTo(8, y - 4);
    c.lineTo(30, y - 4);
    c.stroke();
    c.fillStyle = '#1d2430';
    c.fillText(s.label, 36, y);
  });
  return new Promise((resolve) => out.toBlob((b) => {
    download(b, name);
    resolve(b);
  }, 'image/png'));
}

// columns [time, ...values] (as uPlot holds them) as CSV text: the header "time,NAME,...",
// then one row per sample; a missing value (null: a series chosen after the others) is empty.
// Numbers are written as JavaScript's shortest round-trip form, so they read back exactly.
export function csvText(names, columns) {
  const cell = (v) => (v === null || v === undefined ? '' : String(v));
  const quote = (n) => (/[",\n]/.test(n) ? `"${n.replaceAll('"', '""')}"` : n);
  const lines = [['time', ...names].map(quote).join(',')];
  const rows = columns.length > 0 ? columns[0].length : 0;
  for (let i = 0; i < rows; ++i) lines.push(columns.map((c) => cell(c[i])).join(','));
  return `${lines.join('\n')}\n`;
}

// a plot's box: a header (its title, the given buttons, PNG, CSV and ×), a place for its series
// picker, its chart and a hint under it; { el, png, csv, close, pickHolder, chart }
export function plotBox({ id, className, title, buttons = [], hint }) {
  const el = document.createElement('div');
  el.className = className;
  el.id = id;
  const header = document.createElement('header');
  const name = document.createElement('span');
  name.className = 'title';
  name.textContent = title;
  const png = document.createElement('button');
  png.textContent = 'PNG';
  png.className = 'export-png';
  png.title = 'Download this plot as a PNG picture';
  const csv = document.createElement('button');
  csv.textContent = 'CSV';
  csv.className = 'export-csv';
  csv.title = 'Download the plotted series as CSV (time, then one column per series)';
  const close = document.createElement('button');
  close.textContent = '×';
  close.title = 'Remove this plot';
  header.append(name, ...buttons, png, csv, close);
  const pickHolder = document.createElement('div');
  const chart = document.createElement('div');
  const tip = document.createElement('div');
  tip.className = 'hint';
  tip.textContent = hint;
  el.append(header, pickHolder, chart, tip);
  return { el, png, csv, close, pickHolder, chart };
}
