// Checks kezuri view pages in headless Chromium (WebGL2 on SwiftShader):
//   node check.mjs PAGE.html… [--out DIR]
// Each page: no console or page error, the first frame comes (data-ready="1"), the picture is not
// blank, the path's colours are where the page's projection puts its vertices, the slider changes
// the picture, readouts never say NaN, the text follows the move and a click on a line or on a
// segment moves to it. Then a copy of the first page with hostile text (program text, title,
// notes, a mark) must show that text literally and open no dialog.
// Prints one JSON object; exits 1 when a check fails.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import zlib from 'node:zlib';
import { open, load } from './chromium.mjs';

const argv = process.argv.slice(2);
const outIdx = argv.indexOf('--out');
const outDir = outIdx >= 0 ? argv.splice(outIdx, 2)[1] : fs.mkdtempSync(path.join(os.tmpdir(), 'kezuri-view-check-'));
const files = argv.filter((a) => !a.startsWith('--'));
if (!files.length) { console.error('usage: node check.mjs PAGE.html… [--out DIR]'); process.exit(2); }
fs.mkdirSync(outDir, { recursive: true });

// ---- PNG (8-bit RGB or RGBA, not interlaced: what Chromium writes) → RGBA pixels
function decodePng(buf) {
  let off = 8, w = 0, h = 0, depth = 0, type = 0, interlace = 0;
  const idat = [];
  while (off < buf.length) {
    const len = buf.readUInt32BE(off), name = buf.toString('latin1', off + 4, off + 8), data = buf.subarray(off + 8, off + 8 + len);
    if (name === 'IHDR') { w = data.readUInt32BE(0); h = data.readUInt32BE(4); depth = data[8]; type = data[9]; interlace = data[12]; }
    else if (name === 'IDAT') idat.push(data);
    else if (name === 'IEND') break;
    off += 12 + len;
  }
  if (depth !== 8 || (type !== 2 && type !== 6) || interlace) throw new Error('unexpected PNG form');
  const bpp = type === 6 ? 4 : 3, stride = w * bpp, raw = zlib.inflateSync(Buffer.concat(idat));
  const px = new Uint8Array(w * h * 4);
  let prev = new Uint8Array(stride);
  for (let y = 0; y < h; y++) {
    const f = raw[y * (stride + 1)], line = Uint8Array.from(raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1)));
    for (let x = 0; x < stride; x++) {
      const a = x >= bpp ? line[x - bpp] : 0, b = prev[x], c = x >= bpp ? prev[x - bpp] : 0;
      let p = 0;
      if (f === 1) p = a; else if (f === 2) p = b; else if (f === 3) p = (a + b) >> 1;
      else if (f === 4) { const q = a + b - c, qa = Math.abs(q - a), qb = Math.abs(q - b), qc = Math.abs(q - c); p = qa <= qb && qa <= qc ? a : qb <= qc ? b : c; }
      line[x] = (line[x] + p) & 255;
    }
    for (let x = 0; x < w; x++) {
      const o = (y * w + x) * 4;
      px[o] = line[x * bpp]; px[o + 1] = line[x * bpp + 1]; px[o + 2] = line[x * bpp + 2]; px[o + 3] = bpp === 4 ? line[x * bpp + 3] : 255;
    }
    prev = line;
  }
  return { w, h, px };
}
const at = (img, x, y) => { const o = (y * img.w + x) * 4; return [img.px[o], img.px[o + 1], img.px[o + 2]]; };
const near = (c, p, tol) => Math.abs(c[0] - p[0]) <= tol && Math.abs(c[1] - p[1]) <= tol && Math.abs(c[2] - p[2]) <= tol;
function differing(a, b) {
  let n = 0;
  for (let i = 0; i < a.px.length; i += 4) if (a.px[i] !== b.px[i] || a.px[i + 1] !== b.px[i + 1] || a.px[i + 2] !== b.px[i + 2]) n++;
  return n;
}

// ---- one page
async function checkPage(file, label, hostile) {
  const b = await open();
  const { page, problems, dialogs } = b;
  const checks = {};
  const ok = (name, pass, detail) => { checks[name] = { ok: !!pass, ...(detail === undefined ? {} : { detail }) }; return !!pass; };
  const shots = [];
  const canvasShot = async (name) => {
    const rect = await page.evaluate(() => { const r = window.kezuriView.canvas.getBoundingClientRect(); return { x: r.left, y: r.top, width: r.width, height: r.height }; });
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    const buf = await page.screenshot({ clip: rect });
    const f = path.join(outDir, label + '-' + name + '.png');
    fs.writeFileSync(f, buf);
    shots.push(f);
    return decodePng(buf);
  };
  try {
    const l = await load(page, file);
    if (!ok('first frame', l.ready && !l.error, l.error || (l.ready ? l.readyMs && +l.readyMs.toFixed(0) + ' ms' : 'never ready'))) return { page: file, checks, problems, dialogs, shots };
    const info = await page.evaluate(() => {
      const v = window.kezuriView, meta = JSON.parse(document.getElementById('kz-meta').textContent);
      const msg = document.getElementById('kz-message');
      return { moves: v.moves, meta, palette: v.palette, colourBy: v.colourBy(), message: msg.hidden ? '' : msg.textContent, state: v.state() };
    });
    const { meta } = info;
    const full = await page.screenshot({ fullPage: false });
    fs.writeFileSync(path.join(outDir, label + '-page.png'), full);
    shots.push(path.join(outDir, label + '-page.png'));
    const img = await canvasShot('full');
    const bg = info.palette.background;
    let notBg = 0;
    for (let i = 0; i < img.px.length; i += 4) if (!near([img.px[i], img.px[i + 1], img.px[i + 2]], bg, 3)) notBg++;
    ok('title shown', await page.evaluate((t) => document.getElementById('kz-title').textContent === t, String(meta.title || 'kezuri view')));
    ok('notes shown', await page.evaluate((n) => document.querySelectorAll('#kz-notes li').length === n, (meta.notes || []).length));
    ok('rotary note', (await page.evaluate(() => !document.getElementById('kz-rotary').hidden)) === !!meta.rotary);
    if (meta.sim && meta.sim.deviation) {
      const cb = await page.evaluate(() => { const e = document.getElementById('kz-colorbar'); return e.hidden ? '' : e.textContent; });
      ok('colour bar', cb.includes(meta.sim.deviation.scale_basis) && cb.includes('µm'), cb);
    }
    // opens framed on the whole job: its box on the canvas, filling a good part of it
    if (meta.bbox_mm) {
      const f = await page.evaluate((bb) => {
        const v = window.kezuriView, c = v.canvas;
        let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
        for (let m = 0; m < 8; m++) {
          const [x, y] = v.project([bb[m & 1][0], bb[(m >> 1) & 1][1], bb[(m >> 2) & 1][2]]);
          x0 = Math.min(x0, x); y0 = Math.min(y0, y); x1 = Math.max(x1, x); y1 = Math.max(y1, y);
        }
        return { box: [x0, y0, x1, y1].map((q) => Math.round(q)), w: c.clientWidth, h: c.clientHeight };
      }, meta.bbox_mm);
      const [x0, y0, x1, y1] = f.box;
      ok('opens framed on the job', x0 >= -2 && y0 >= -2 && x1 <= f.w + 2 && y1 <= f.h + 2 && (x1 - x0 > 0.4 * f.w || y1 - y0 > 0.4 * f.h), f);
    }
    const nan = async () => page.evaluate(() => /NaN|undefined|Infinity/.test(document.getElementById('kz-side').innerText + document.getElementById('kz-play').innerText + document.getElementById('kz-scale').innerText));
    ok('no NaN at the end', !(await nan()));

    const moving = meta.moves > 0 && meta.vertices > 1 && meta.bbox_mm && [0, 1, 2].some((a) => meta.bbox_mm[1][a] > meta.bbox_mm[0][a]);
    if (!moving) {
      ok('message for nothing to show', info.message.length > 10, info.message);
      ok('not blank', notBg > 100, notBg + ' pixels');
      ok('no NaN at move 0', (await page.evaluate(() => window.kezuriView.setMove(0)), !(await nan())));
    } else {
      ok('no message', info.message === '', info.message);
      ok('not blank', notBg > 0.002 * img.w * img.h, notBg + ' of ' + img.w * img.h + ' pixels not background');
      // the path's colours where the projection puts the vertices (the part hidden: it may cover them)
      const hasPart = await page.evaluate(() => !document.getElementById('kz-part-toggle').hidden);
      if (hasPart) await page.click('#kz-show-part');
      const pathImg = await canvasShot('path');
      const samples = await page.evaluate((meta) => {
        const v = window.kezuriView, c = v.canvas, r = c.getBoundingClientRect(), out = [], seen = new Set();
        for (let s = 0; s < 2000 && out.length < 60; s++) {
          const k = Math.floor(((s * 7919) % 2000) / 2000 * v.vertices);
          if (seen.has(k)) continue;
          seen.add(k);
          const p = v.vertex(k);
          if (!p) continue;
          const [x, y] = v.project(p);
          if (!(x >= 3 && y >= 3 && x < c.clientWidth - 3 && y < c.clientHeight - 3)) continue;
          if (document.elementFromPoint(r.left + x, r.top + y) !== c) continue;   // under the legend, a pin, …
          out.push([k, Math.round(x), Math.round(y)]);
        }
        // the tool drawn at the current position covers what is under it: its box on the screen
        const t = v.state().posMm;
        let box = [0, 0, -1, -1];
        if (t) {
          const prof = (meta.tools || []).flatMap((tl) => tl.profile || []);
          const r = Math.max(1, ...prof.map((q) => q[1])), h = Math.max(1, ...prof.map((q) => q[0]));
          box = [Infinity, Infinity, -Infinity, -Infinity];
          for (const d of [[r, r, 0], [r, -r, 0], [-r, r, 0], [-r, -r, 0], [r, r, h], [r, -r, h], [-r, r, h], [-r, -r, h]]) {
            const q = v.project([t[0] + d[0], t[1] + d[1], t[2] + d[2]]);
            box = [Math.min(box[0], q[0] - 8), Math.min(box[1], q[1] - 8), Math.max(box[2], q[0] + 8), Math.max(box[3], q[1] + 8)];
          }
        }
        return { out, box };
      }, meta);
      const colours = [...(info.colourBy === 'tool' ? info.palette.tool : info.palette.kind), [140, 140, 140]];
      let hit = 0, tried = 0;
      for (const [, x, y] of samples.out) {
        const bx = samples.box;
        if (x >= bx[0] && x <= bx[2] && y >= bx[1] && y <= bx[3]) continue;
        tried++;
        let found = false;
        for (let dy = -2; dy <= 2 && !found; dy++) for (let dx = -2; dx <= 2 && !found; dx++) {
          const c = at(pathImg, Math.min(pathImg.w - 1, Math.max(0, x + dx)), Math.min(pathImg.h - 1, Math.max(0, y + dy)));
          if (colours.some((p) => near(c, p, 24))) found = true;
        }
        if (found) hit++;
      }
      ok('path colours at projected vertices', tried >= 1 && hit >= 0.8 * tried, hit + ' of ' + tried + ' vertices in view');
      // picking: a click on the view goes to the move the page picks there; the background picks nothing
      const target = samples.out[Math.floor(samples.out.length / 2)] || samples.out[0];
      if (target) {
        const r = await page.evaluate(() => { const b = window.kezuriView.canvas.getBoundingClientRect(); return [b.left, b.top]; });
        const want = await page.evaluate(([x, y]) => window.kezuriView.pick(x, y), [target[1], target[2]]);
        await page.mouse.click(r[0] + target[1], r[1] + target[2]);
        const got = await page.evaluate(() => window.kezuriView.state().move);
        ok('click on a segment goes to its move', want >= 0 && got === want + 1, { want: want + 1, got });
      }
      let empty = null;
      for (let y = 4; y < pathImg.h - 4 && !empty; y += 23) for (let x = 4; x < pathImg.w - 4 && !empty; x += 23) {
        let clear = true;
        for (let dy = -9; dy <= 9 && clear; dy++) for (let dx = -9; dx <= 9 && clear; dx++) {
          const xx = x + dx, yy = y + dy;
          if (xx >= 0 && yy >= 0 && xx < pathImg.w && yy < pathImg.h && !near(at(pathImg, xx, yy), bg, 3)) clear = false;
        }
        if (clear) empty = [x, y];
      }
      if (empty) ok('background picks nothing', (await page.evaluate(([x, y]) => window.kezuriView.pick(x, y), empty)) === -1, empty);
      // the camera: the wheel zooms about the cursor, a right drag pans by the drag, a left drag orbits
      if (target) {
        const r = await page.evaluate(() => { const b = window.kezuriView.canvas.getBoundingClientRect(); return [b.left, b.top]; });
        const p = await page.evaluate((k) => window.kezuriView.vertex(k), target[0]);
        const proj = () => page.evaluate((q) => window.kezuriView.project(q), p);
        const p0 = await proj();
        await page.mouse.move(r[0] + p0[0], r[1] + p0[1]);
        await page.mouse.wheel(0, -300);
        const scale0 = await page.evaluate(() => document.getElementById('kz-scale-label').textContent);
        const p1 = await proj();
        ok('wheel zooms about the cursor', Math.hypot(p1[0] - p0[0], p1[1] - p0[1]) < 1.5, { before: p0, after: p1 });
        await page.mouse.down({ button: 'right' });
        await page.mouse.move(r[0] + p0[0] + 40, r[1] + p0[1] + 25, { steps: 4 });
        await page.mouse.up({ button: 'right' });
        const p2 = await proj();
        ok('right drag pans', Math.hypot(p2[0] - p1[0] - 40, p2[1] - p1[1] - 25) < 1.5, { before: p1, after: p2 });
        const before = await canvasShot('pan');
        const moveBefore = await page.evaluate(() => window.kezuriView.state().move);
        await page.mouse.move(r[0] + 100, r[1] + 100);
        await page.mouse.down();
        await page.mouse.move(r[0] + 160, r[1] + 120, { steps: 4 });
        await page.mouse.up();
        const after = await canvasShot('orbit');
        const d = differing(before, after);
        const moveAfter = await page.evaluate(() => window.kezuriView.state().move);
        ok('left drag orbits (and picks nothing)', d > 100 && moveAfter === moveBefore, d + ' pixels differ');
        await page.click('button[data-view="fit"]');
        const scale1 = await page.evaluate(() => document.getElementById('kz-scale-label').textContent);
        ok('scale bar', /^[125]0*(\.0*)? (mm|in)$|^0\.0*[125] (mm|in)$/.test(scale0) && /(mm|in)$/.test(scale1), [scale0, scale1]);
      }
      if (hasPart) await page.click('#kz-show-part');
      // the tool only where the program put it: never at a reference point or G53 position the
      // page does not know (drawn there, it would stand in the part); such moves said in the legend
      const unplaced = await page.evaluate(() => {
        const v = window.kezuriView, out = [];
        for (let m = 0; m < v.moves; m++) if (v.kindOf(m) === 'position not known') out.push(m);
        return out;
      });
      if (unplaced.length) {
        const legendText = await page.evaluate(() => document.getElementById('kz-legend').textContent);
        ok('legend says what is not drawn', legendText.includes('not drawn: ' + unplaced.length.toLocaleString('en-US') + ' move'), legendText);
        const hidden = [];
        for (const m of unplaced.slice(0, 20)) {
          const st = await page.evaluate((n) => { window.kezuriView.setMove(n); return window.kezuriView.state(); }, m + 1);
          if (st.toolShown !== false || st.posMm !== null) hidden.push({ move: m + 1, state: st });
        }
        ok('no tool at a place not known', hidden.length === 0, hidden.slice(0, 3));
        // in pixels: the path hidden, the last move (a return) shows nothing but the axes, as
        // another unplaced move does; a placed move shows the tool
        await page.click('#kz-show-path');
        await page.evaluate(() => window.kezuriView.setMove(window.kezuriView.moves));
        const atEnd = await canvasShot('end-no-path');
        await page.evaluate((n) => window.kezuriView.setMove(n), unplaced[0] + 1);
        const atOther = await canvasShot('unplaced-no-path');
        const placedMove = await page.evaluate(() => { const v = window.kezuriView; for (let m = Math.floor(v.moves / 2); m < v.moves; m++) if (v.kindOf(m) !== 'position not known') return m; return -1; });
        await page.evaluate((n) => window.kezuriView.setMove(n), placedMove + 1);
        const atPlaced = await canvasShot('placed-no-path');
        await page.click('#kz-show-path');
        const last = await page.evaluate(() => window.kezuriView.kindOf(window.kezuriView.moves - 1));
        const same = differing(atEnd, atOther), shown = differing(atEnd, atPlaced);
        ok('tool not drawn at the end (a return)', last !== 'position not known' || same === 0, same + ' pixels differ');
        ok('tool drawn where placed', placedMove >= 0 && shown > 50, shown + ' pixels differ');
        await page.evaluate(() => window.kezuriView.setMove(window.kezuriView.moves));
      }
      // the slider (as a user moves it) changes the picture and the readout
      const half = Math.floor(info.moves / 2);
      await page.evaluate((n) => { const s = document.getElementById('kz-slider'); s.value = String(n); s.dispatchEvent(new Event('input', { bubbles: true })); }, half);
      const halfImg = await canvasShot('half');
      const st = await page.evaluate(() => window.kezuriView.state());
      ok('slider moves', st.move === half, st.move);
      const d = differing(halfImg, img);
      ok('slider changes the picture', d > 50, d + ' pixels differ');
      ok('no NaN halfway', !(await nan()));
      const ms = await page.evaluate(() => window.kezuriView.setMove(0));
      ok('no NaN at move 0', !(await nan()) && Number.isFinite(ms));
      await page.evaluate(() => window.kezuriView.setMove(window.kezuriView.moves));
      // step buttons
      await page.evaluate((n) => window.kezuriView.setMove(n), half);
      await page.click('#kz-steps button[data-step="-100"]');
      const back = await page.evaluate(() => window.kezuriView.state().move);
      ok('step button', back === Math.max(0, half - 100), back);
    }
    // the program text: the current line is highlighted; a click on a line goes to its first move
    if (meta.text) {
      await page.waitForFunction(() => document.querySelectorAll('#kz-program-rows .kz-line').length > 0, null, { timeout: 60000 });
      if (meta.moves > 0) {
        const m = Math.floor(meta.moves / 3) + 1;
        await page.evaluate((n) => window.kezuriView.setMove(n), m);
        const t = await page.evaluate(() => {
          const cur = document.querySelector('#kz-program-rows .kz-line.cur:not([hidden])');
          return { line: window.kezuriView.state().line, cur: cur ? Number(cur.querySelector('.kz-ln').textContent) : null };
        });
        ok('current line highlighted', t.line < 1 || t.cur === t.line, t);
        const rows = await page.$$('#kz-program-rows .kz-line:not([hidden])');
        const row = rows[Math.min(rows.length - 1, 4)];
        if (row) {
          const ln = Number(await row.$eval('.kz-ln', (e) => e.textContent));
          await row.click();
          const s = await page.evaluate(() => window.kezuriView.state());
          ok('click on a line goes to its first move', s.line >= ln, { clicked: ln, state: s });
        }
      }
      if (hostile) {
        const seen = await page.evaluate(() => {
          const el = document.getElementById('kz-program');
          el.scrollTop = 0;
          el.dispatchEvent(new Event('scroll'));
          return new Promise((r) => requestAnimationFrame(() => r({
            text: document.getElementById('kz-program-rows').textContent,
            title: document.getElementById('kz-title').textContent,
            notes: document.getElementById('kz-notes').textContent,
            marks: document.getElementById('kz-marks').textContent,
            imgs: document.querySelectorAll('img').length,
            scripts: document.scripts.length,
          })));
        });
        for (const p of HOSTILE) ok('literal in text: ' + p, seen.text.includes(p));
        ok('literal in title', seen.title.includes(HOSTILE[0]));
        ok('literal in notes', seen.notes.includes(HOSTILE[1]));
        ok('literal in marks', seen.marks.includes(HOSTILE[1]));
        ok('no element made from text', seen.imgs === 0 && seen.scripts === 4, seen);
      }
    }
    if (hostile) ok('no dialog', dialogs.length === 0, dialogs);
  } catch (e) {
    ok('ran', false, String((e && e.stack) || e));
  } finally {
    await b.close();
  }
  ok('no console or page errors', problems.length === 0, problems.slice(0, 10));
  if (dialogs.length) ok('no dialog', false, dialogs);
  return { page: file, ok: Object.values(checks).every((c) => c.ok), checks, shots };
}

// ---- a copy of a page with hostile text in every place that takes text from the program
const HOSTILE = ['</script><script>alert(1)</script>', '<img src=x onerror=alert(1)>'];
function hostileCopy(file) {
  let html = fs.readFileSync(file, 'utf8');
  const metaRe = /(<script type="application\/json" id="kz-meta">)([\s\S]*?)(<\/script>)/;
  const m = metaRe.exec(html);
  if (!m) throw new Error(file + ': no kz-meta');
  const meta = JSON.parse(m[2]);
  const textRe = /(<script type="application\/octet-stream" id="kz-text">)([\s\S]*?)(<\/script>)/;
  const t = textRe.exec(html);
  let lines = t ? zlib.gunzipSync(Buffer.from(t[2], 'base64')).toString('utf8').split('\n') : [];
  if (lines.length >= 2) { lines[0] = HOSTILE[0]; lines[1] = HOSTILE[1]; } else lines = [...HOSTILE, ...lines];
  const packed = zlib.gzipSync(Buffer.from(lines.join('\n'), 'utf8')).toString('base64');
  meta.title = 'hostile ' + HOSTILE[0] + '.nc';
  meta.notes = [...(meta.notes || []), 'note ' + HOSTILE[1]];
  meta.marks = [...(meta.marks || []), { kind: 'gouge', label: 'mark ' + HOSTILE[1], at_mm: meta.origin_mm, move: null, line: 1 }];
  meta.text = true;
  const json = JSON.stringify(meta).replace(/</g, '\\u003c').replace(/>/g, '\\u003e').replace(/&/g, '\\u0026');
  html = html.replace(metaRe, (_, a, __, c) => a + json + c);
  if (t) html = html.replace(textRe, (_, a, __, c) => a + packed + c);
  else {
    const i = html.lastIndexOf('<script>');
    html = html.slice(0, i) + '<script type="application/octet-stream" id="kz-text">' + packed + '</script>\n' + html.slice(i);
  }
  const out = path.join(outDir, 'hostile.html');
  fs.writeFileSync(out, html);
  return out;
}

const results = [];
for (const [i, f] of files.entries()) results.push(await checkPage(f, 'p' + i + '-' + path.basename(f, '.html'), false));
results.push(await checkPage(hostileCopy(files[0]), 'hostile', true));
const allOk = results.every((r) => r.ok);
console.log(JSON.stringify({ ok: allOk, out: outDir, pages: results }, null, 1));
process.exit(allOk ? 0 : 1);
