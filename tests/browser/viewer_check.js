// Drives Debian's Chromium headless (puppeteer-core) over a brdfit HTML report opened
// from disk, and checks the viewer as a reader would use it (tests/cli_viewer.sh):
//  - the page loads with no console error, no page error and no failed request;
//  - every sphere draws (lit pixels inside the disc);
//  - dragging on a sphere moves the light and changes the picture;
//  - the incidence slider moves the slice;
//  - the table's link to a model's view selects that model;
//  - window.brdfitViewer.value agrees with reference values (brdfit eval, the
//    measurement's reader) within a relative tolerance, away from sharp peaks.
//
//   node viewer_check.js SPEC.json
//
// SPEC: {"report": DIR, "shots": DIR or null, "chromium": PATH,
//        "tolerance": {"model": {"p95": P, "max": M}, "measured": {...}},
//        "min_theta_h": DEG, "max_theta": DEG,
//        "values": [{"material": ID, "model": NAME, "dirs": CSV, "expected": CSV,
//                    "expected_swapped": CSV or absent (the reference at o, i)}, ...]}
// dirs and expected are CSV files with a header; expected has a row for each of dirs' (in
// any order, matched by angles): the four angles, then the channels (r, g, b, or any other count, compared by their mean). Prints "ok ..." / "FAIL ..." lines; exit 1 on any failure.
'use strict';
const fs = require('fs');
const path = require('path');
const puppeteer = require(path.join(__dirname, '..', '..', 'tools', 'node_modules', 'puppeteer-core'));

const spec = JSON.parse(fs.readFileSync(process.argv[2], 'utf8'));
let failures = 0;
function ok(what) { console.log(`ok ${what}`); }
function bad(what) { console.log(`FAIL ${what}`); failures++; }
function check(cond, what) { if (cond) ok(what); else bad(what); }

function readCsv(file) {
  const lines = fs.readFileSync(file, 'utf8').trim().split('\n');
  return lines.slice(1).map((l) => l.split(',').map(Number));
}

function dirOf(l) {
  const r = Math.PI / 180;
  return [Math.sin(l.theta * r) * Math.cos(l.phi * r), Math.sin(l.theta * r) * Math.sin(l.phi * r), Math.cos(l.theta * r)];
}
function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

function thetaH(d) {
  const v = (t, p) => [Math.sin(t) * Math.cos(p), Math.sin(t) * Math.sin(p), Math.cos(t)];
  const r = Math.PI / 180, L = v(d[0] * r, d[1] * r), V = v(d[2] * r, d[3] * r);
  const h = [L[0] + V[0], L[1] + V[1], L[2] + V[2]];
  return Math.acos(h[2] / Math.hypot(h[0], h[1], h[2])) / r;
}

// Pixels of a canvas, as an array of RGBA bytes.
async function pixels(page, selector) {
  return page.$eval(selector, (c) => Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data));
}
function litInDisc(px, size) {
  let lit = 0;
  for (let y = 0; y < size; y++)
    for (let x = 0; x < size; x++) {
      const sx = 2 * (x + 0.5) / size - 1, sy = 1 - 2 * (y + 0.5) / size, o = 4 * (y * size + x);
      if (sx * sx + sy * sy < 0.95 && px[o] + px[o + 1] + px[o + 2] > 6) lit++;
    }
  return lit;
}
function differ(a, b) {
  let n = 0;
  for (let q = 0; q < a.length; q++) if (Math.abs(a[q] - b[q]) > 2) n++;
  return n;
}

(async () => {
  const profile = fs.mkdtempSync('/tmp/brdfit-chromium-');
  const browser = await puppeteer.launch({
    executablePath: spec.chromium, headless: true, userDataDir: profile,
    // --no-sandbox: Chromium refuses its sandbox as root; the page is our own file.
    // SwiftShader: WebGL on the CPU, as on a machine with no GPU.
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-background-networking',
           '--disable-component-update', '--no-first-run'],
  });
  try {
    const page = await browser.newPage();
    await page.setViewport({width: 1280, height: 1000});
    const errors = [];
    page.on('console', (m) => { if (m.type() === 'error') errors.push(`console ${m.type()}: ${m.text()}`); });
    page.on('pageerror', (e) => errors.push(`page error: ${e.message}`));
    page.on('requestfailed', (r) => errors.push(`request failed: ${r.url()}`));
    page.on('request', (r) => { if (!r.url().startsWith('file://') && !r.url().startsWith('data:')) errors.push(`off-disk request: ${r.url()}`); });
    const url = 'file://' + path.resolve(spec.report, 'index.html');
    await page.goto(url, {waitUntil: 'load'});
    const ids = await page.evaluate(() => window.brdfitViewer.ready);
    check(Array.isArray(ids) && ids.length > 0, `viewer ready: ${ids}`);

    for (const id of ids) {
      const models = await page.evaluate((m) => window.brdfitViewer.models(m), id);
      const spheres = await page.$$eval(`#viewer-${id} canvas.sphere`, (cs) => cs.map((c) => c.dataset.source));
      for (const s of spheres) {
        const px = await pixels(page, `#viewer-${id} canvas.sphere[data-source="${s}"]`);
        const lit = litInDisc(px, 160);
        check(lit > 2000, `${id} ${s}: sphere drawn (${lit} lit pixels in the disc)`);
      }
      check(spheres.length >= models.length - 1, `${id}: a sphere per model (${spheres.join(' ')} of ${models.join(' ')})`);
      if (spec.shots) await (await page.$(`#viewer-${id}`)).screenshot({path: path.join(spec.shots, `${id}.png`)});

      // Drag on the first sphere from its centre to the upper left.
      const first = `#viewer-${id} canvas.sphere`;
      const before = await pixels(page, first), light0 = await page.evaluate((m) => window.brdfitViewer.light(m), id);
      // Mouse events reach what is in the viewport: the sphere is scrolled to first.
      await page.$eval(first, (e) => e.scrollIntoView({block: 'center'}));
      const box = await (await page.$(first)).boundingBox();
      await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
      await page.mouse.down();
      await page.mouse.move(box.x + box.width * 0.25, box.y + box.height * 0.3, {steps: 5});
      await page.mouse.up();
      const after = await pixels(page, first), light1 = await page.evaluate((m) => window.brdfitViewer.light(m), id);
      const turned = Math.acos(Math.min(1, dot(dirOf(light0), dirOf(light1)))) * 180 / Math.PI;
      check(turned > 20 && differ(before, after) > 1000,
            `${id}: dragging moves the light (${light0.theta.toFixed(1)}/${light0.phi.toFixed(1)} -> ` +
            `${light1.theta.toFixed(1)}/${light1.phi.toFixed(1)} deg) and the picture (${differ(before, after)} bytes)`);
      // The light is up and to the left of the view: azimuth in (90, 180).
      check(light1.phi > 90 && light1.phi < 180, `${id}: light azimuth follows the pointer (${light1.phi.toFixed(1)})`);

      // The slider: the slice changes, and the viewer reports the new incidence.
      const slider = `#viewer-${id} input[aria-label="incidence"]`, slice = `#viewer-${id} canvas.slice`;
      const s0 = await pixels(page, slice);
      await page.$eval(slider, (e) => { e.value = '60'; e.dispatchEvent(new Event('input')); });
      const s1 = await pixels(page, slice), inc = await page.evaluate((m) => window.brdfitViewer.incidence(m), id);
      check(inc === 60 && differ(s0, s1) > 500, `${id}: the slider moves the slice (incidence ${inc}, ${differ(s0, s1)} bytes)`);
      // The readout under the pointer names every shown model.
      await page.$eval(slice, (e) => e.scrollIntoView({block: 'center'}));
      const sb = await (await page.$(slice)).boundingBox();
      await page.mouse.move(sb.x + sb.width * 0.5, sb.y + sb.height * 0.5);
      const text = await page.$eval(`#viewer-${id} pre.readout`, (e) => e.textContent);
      check(models.slice(1).every((m) => text.includes(m + ':')), `${id}: readout under the pointer: ${JSON.stringify(text)}`);
    }

    // The table's links: a model's name selects it in its material's half/difference images.
    const link = await page.$('a[href^="#m1-view-"]:last-of-type');
    if (link) {
      const href = await page.evaluate((a) => a.getAttribute('href'), link);
      await link.click();
      await page.waitForFunction((h) => location.hash === h, {}, href);
      const want = href.split('-').pop();
      const got = await page.$eval('#viewer-m1 select', (s) => s.value);
      check(got === want, `link ${href} selects model ${want} (select shows ${got})`);
    } else {
      bad('no link from the table of fits to a model view');
    }

    // Values against the references, away from sharp peaks.
    const tol = spec.tolerance;
    for (const v of spec.values) {
      const dirs = readCsv(v.dirs), want = readCsv(v.expected);
      // A measurement that is not reciprocal (RGL files: f(i, o) != f(o, i) near the
      // highlight) has one value per reciprocal pair in the viewer, as on the MERL grid it
      // is tabulated from: compared with the nearer of the reader's two values.
      // Rows are matched by their angles: a reader may group them by incidence.
      const byAngles = (rows) => new Map(rows.map((r) => [r.slice(0, 4).map((x) => x.toFixed(4)).join(','), r]));
      const swappedRows = v.expected_swapped ? byAngles(readCsv(v.expected_swapped)) : null;
      const swapped = swappedRows ? dirs.map((d) => swappedRows.get([d[2], d[3], d[0], d[1]].map((x) => x.toFixed(4)).join(','))) : null;
      const wantRows = byAngles(want), wanted = dirs.map((d) => wantRows.get(d.slice(0, 4).map((x) => x.toFixed(4)).join(',')));
      check(wanted.every(Boolean) && (!swapped || swapped.every(Boolean)),
            `${v.material} ${v.model}: a reference value for every direction`);
      const use = dirs.map((d, q) => [d, wanted[q], q]).filter(([d, w, q]) => w && (!swapped || swapped[q]) &&
        thetaH(d) >= spec.min_theta_h && d[0] <= spec.max_theta && d[2] <= spec.max_theta);
      const got = await page.evaluate((m, model, ds) => ds.map((d) => window.brdfitViewer.value(m, model, ...d)),
                                      v.material, v.model, use.map(([d]) => d.slice(0, 4)));
      // The viewer shows 3 channels as RGB and any other count as their mean (grey).
      const rgb = (w) => {
        const e = w.slice(4);
        if (e.length === 3) return e;
        const mean = e.reduce((a, b) => a + b, 0) / e.length;
        return [mean, mean, mean];
      };
      // Relative error, with a floor of 1% of the largest reference value of the set so
      // that values near 0 (a measurement's noise) do not count as large errors.
      const floor = 0.01 * Math.max(...use.map(([, w]) => Math.max(...rgb(w))));
      let worst = 0, where = null, nulls = 0, reversed = 0;
      const errs = [];
      use.forEach(([d, w], q) => {
        const g = got[q];
        if (!g) { nulls++; return; }
        const e = rgb(w), e2 = swapped ? rgb(swapped[use[q][2]]) : null;
        for (let c = 0; c < 3; c++) {
          if (e2 && Math.abs(g[c] - e2[c]) < Math.abs(g[c] - e[c])) { e[c] = e2[c]; reversed++; }
          const err = Math.abs(g[c] - e[c]) / Math.max(Math.abs(e[c]), floor, 1e-12);
          errs.push(err);
          if (err > worst) { worst = err; where = `${d.slice(0, 4).join(',')} ch ${c}: ${g[c].toPrecision(5)} vs ${e[c].toPrecision(5)}`; }
        }
      });
      errs.sort((a, b) => a - b);
      const p95 = errs.length ? errs[Math.floor(0.95 * (errs.length - 1))] : NaN;
      const t = tol[v.model === 'measured' ? 'measured' : 'model'];
      check(nulls === 0 && use.length >= 20 && p95 <= t.p95 && worst <= t.max,
            `${v.material} ${v.model}: ${use.length} directions, relative error 95th percentile ${p95.toFixed(4)}, ` +
            `worst ${worst.toFixed(4)} (tolerance ${t.p95}, ${t.max}${where ? '; worst at ' + where : ''})` +
            `${nulls ? `, ${nulls} without a value` : ''}${swapped ? `; ${reversed} values nearer f(o, i)` : ''}`);
    }
    check(errors.length === 0, `no console error, page error or request off the disk${errors.length ? ': ' + errors.join('; ') : ''}`);
  } finally {
    await browser.close();
    fs.rmSync(profile, {recursive: true, force: true});
  }
  process.exit(failures ? 1 : 0);
})().catch((e) => { console.log(`FAIL ${e.stack || e}`); process.exit(1); });
