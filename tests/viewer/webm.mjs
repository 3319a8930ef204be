// Reads what a test needs of a WebM file (Matroska's EBML): whether it is one, and how long its
// video lasts (MediaRecorder writes no Duration: the last block's time is what counts).
// Usage as a module: webmInfo(buffer) -> { ok, docType, blocks, seconds, error }.
const SEGMENT = 0x18538067;
const CLUSTER = 0x1f43b675;
const BLOCK_GROUP = 0xa0;
const TIMECODE = 0xe7;
const SIMPLE_BLOCK = 0xa3;
const BLOCK = 0xa1;
const TIMECODE_SCALE = 0x2ad7b1;
const INFO = 0x1549a966;
const DOC_TYPE = 0x4282;
const EBML = 0x1a45dfa3;

// a variable-length integer at p: { value, length }; the ID keeps its marker bit, a size not
function vint(b, p, keepMarker) {
  const first = b[p];
  if (first === undefined || first === 0) throw new Error(`bad EBML number at byte ${p}`);
  let length = 1;
  while (!(first & (0x80 >> (length - 1)))) length++;
  let value = keepMarker ? first : first & (0xff >> length);
  let allOnes = value === (0xff >> length);
  for (let i = 1; i < length; i++) {
    if (p + i >= b.length) throw new Error('file cut short');
    value = value * 256 + b[p + i];
    allOnes = allOnes && b[p + i] === 0xff;
  }
  return { value, length, unknown: !keepMarker && allOnes };
}

function uint(b, p, n) {
  let v = 0;
  for (let i = 0; i < n; i++) v = v * 256 + b[p + i];
  return v;
}

export function webmInfo(b) {
  const out = { ok: false, docType: '', blocks: 0, seconds: 0, error: '' };
  try {
    if (b.length < 4 || uint(b, 0, 4) !== EBML) throw new Error('no EBML header');
    let p = 0;
    let scale = 1e6;
    let cluster = 0;
    let first = null;
    let last = null;
    while (p < b.length) {
      const id = vint(b, p, true);
      const size = vint(b, p + id.length, false);
      const body = p + id.length + size.length;
      if (id.value === EBML || id.value === SEGMENT || id.value === CLUSTER ||
          id.value === BLOCK_GROUP || id.value === INFO) {
        if (id.value === EBML) {
          // its children: DocType among them
          let q = body;
          while (q < body + size.value) {
            const cid = vint(b, q, true);
            const cs = vint(b, q + cid.length, false);
            const cb = q + cid.length + cs.length;
            if (cid.value === DOC_TYPE) out.docType = Buffer.from(b.subarray(cb, cb + cs.value)).toString();
            q = cb + cs.value;
          }
          p = body + size.value;
        } else {
          p = body;  // go in
        }
        continue;
      }
      if (size.unknown) throw new Error(`element ${id.value.toString(16)} of unknown size`);
      if (id.value === TIMECODE_SCALE) scale = uint(b, body, size.value);
      if (id.value === TIMECODE) cluster = uint(b, body, size.value);
      if (id.value === SIMPLE_BLOCK || id.value === BLOCK) {
        const track = vint(b, body, false);
        let rel = uint(b, body + track.length, 2);
        if (rel >= 0x8000) rel -= 0x10000;
        const t = cluster + rel;
        if (first === null || t < first) first = t;
        if (last === null || t > last) last = t;
        out.blocks++;
      }
      p = body + size.value;
    }
    out.seconds = first === null ? 0 : (last - first) * scale / 1e9;
    out.ok = out.docType === 'webm' && out.blocks > 0;
    if (!out.ok) out.error = `docType '${out.docType}', ${out.blocks} blocks`;
  } catch (e) {
    out.error = e.message;
  }
  return out;
}
