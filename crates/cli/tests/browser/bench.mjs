// Timings of kezuri view pages in headless Chromium (SwiftShader):
//   node bench.mjs PAGE.html… [--width 1280 --height 800] [--steps 20 --step 1000 --redraws 5]
// Prints JSON: per page its size, load to first frame (readyMs: in a fresh browser, whose GPU
// process starts cold; warmReadyMs: loaded again in the running browser; both from navigation
// start, as the page's performance.now()), the median of the slider steps of --step moves
// forward (stepMedianMs, each until the GPU is done), the median full redraw (redrawMedianMs),
// and the page's own breakdown of its first frame (timings).
import fs from 'node:fs';
import { open, load } from './chromium.mjs';

const argv = process.argv.slice(2);
const opt = (name, d) => { const i = argv.indexOf('--' + name); return i < 0 ? d : Number(argv.splice(i, 2)[1]); };
const width = opt('width', 1280), height = opt('height', 800);
const nSteps = opt('steps', 20), stepSize = opt('step', 1000), nRedraws = opt('redraws', 5);
const files = argv.filter((a) => !a.startsWith('--'));
if (!files.length) { console.error('usage: node bench.mjs PAGE.html… [--width W --height H --steps 20 --step 1000 --redraws 5]'); process.exit(2); }

const median = (a) => { const s = [...a].sort((x, y) => x - y); return s.length ? +(s[(s.length - 1) >> 1] + s[s.length >> 1]).toFixed(3) / 2 : null; };
const results = [];
let failed = false;
for (const file of files) {
  const b = await open({ width, height });
  try {
    // first in a fresh browser (its GPU process starts cold), then again in the running browser
    const l = await load(b.page, file);
    const r = { page: file, bytes: fs.statSync(file).size, viewport: [width, height], ...l };
    if (l.ready) {
      const w = await load(b.page, file);
      r.warmReadyMs = w.readyMs == null ? null : +w.readyMs.toFixed(1);
      r.warmWallMs = w.wallMs;
    }
    if (l.ready) {
      Object.assign(r, await b.page.evaluate(async ({ nSteps, stepSize, nRedraws }) => {
        const v = window.kezuriView;
        const n = v.moves;
        const redraws = [];
        for (let i = 0; i < nRedraws; i++) redraws.push(v.redraw());
        // forward steps from a quarter of the way (incremental drawing)
        const start = Math.max(0, Math.min(Math.floor(n / 4), n - nSteps * stepSize));
        const jumpMs = v.setMove(start);            // a jump back: full redraw
        const steps = [];
        for (let i = 1; i <= nSteps; i++) steps.push(v.setMove(Math.min(n, start + i * stepSize)));
        const back = v.setMove(Math.max(0, start + nSteps * stepSize - stepSize));
        return { moves: n, redraws, steps, jumpMs, stepBackMs: back, timings: v.timings, lodVertices: v.lodVertices };
      }, { nSteps, stepSize, nRedraws }));
      r.readyMs = r.readyMs == null ? null : +r.readyMs.toFixed(1);
      r.stepMedianMs = median(r.steps);
      r.redrawMedianMs = median(r.redraws);
      r.steps = r.steps.map((x) => +x.toFixed(1));
      r.redraws = r.redraws.map((x) => +x.toFixed(1));
    } else failed = true;
    r.problems = b.problems;
    results.push(r);
  } catch (e) {
    failed = true;
    results.push({ page: file, error: String(e && e.message || e), problems: b.problems });
  } finally {
    await b.close();
  }
}
console.log(JSON.stringify(results, null, 1));
process.exit(failed ? 1 : 0);
