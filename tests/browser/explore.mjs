// Browser test of `gonio explore`: Debian's chromium driven by playwright-core, headless.
// Usage: node explore.mjs PATH/TO/gonio [ARTEFACT_DIR]
// Opens the page, picks two models, moves a slider (the plots must change, a shown value must
// equal `gonio eval`), opens a MERL file written by `gonio measure`, waits for the lit sphere,
// reads the check panel, fits, takes screenshots, and fails on any console error. Prints the
// latencies it measured and fails when they miss the targets (2D plots ≤ 50 ms p95, first
// lit-sphere frame ≤ 150 ms).
import { chromium } from 'playwright-core';
import { spawn, execFileSync } from 'node:child_process';
import { mkdtempSync, mkdirSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';

const gonio = resolve(process.argv[2] || '../../target/release/gonio');
const shots = resolve(process.argv[3] || '../../target/explore-screenshots');
mkdirSync(shots, { recursive: true });
const data = mkdtempSync(join(tmpdir(), 'gonio-explore-'));
const PLOT_P95_MS = 50;
const LIT_FIRST_MS = 150;

function check(cond, what) {
  if (!cond) throw new Error('FAILED: ' + what);
  console.log('ok   ' + what);
}

const median = (xs) => xs.slice().sort((a, b) => a - b)[xs.length >> 1];
const p95 = (xs) => { const s = xs.slice().sort((a, b) => a - b); return s[Math.min(s.length - 1, Math.ceil(0.95 * s.length) - 1)]; };

// An item `phong:ks=0.5` as `gonio eval` arguments.
function evalArgs(item) {
  const [name, ...rest] = item.split(':');
  return [name, ...rest.flatMap((kv) => { const i = kv.indexOf('='); return ['--' + kv.slice(0, i), kv.slice(i + 1)]; })];
}

execFileSync(gonio, ['measure', 'ggx', '--alpha', '0.2', '--diffuse', '0.2,0.1,0.05', '-o', join(data, 'gold.binary')], { stdio: 'inherit' });

const server = spawn(gonio, ['explore', '--port', '0', '--data', data], { stdio: ['ignore', 'pipe', 'inherit'] });
const url = await new Promise((ok, fail) => {
  let out = '';
  server.stdout.on('data', (d) => { out += d; const m = out.match(/serving (http:\S+)/); if (m) ok(m[1]); });
  server.on('exit', (c) => fail(new Error('gonio explore exited with ' + c)));
  setTimeout(() => fail(new Error('gonio explore printed no address')), 20000);
});

const browser = await chromium.launch({ executablePath: process.env.CHROMIUM || '/usr/bin/chromium', headless: true, args: ['--no-sandbox'] });
const errors = [];
try {
  const page = await browser.newPage({ viewport: { width: 1440, height: 900 } });
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url);
  await page.waitForFunction(() => window.gonioReady && window.gonioStats.plotLatencies.length > 0);
  check(await page.locator('.card').count() === 1, 'the page opens with one model');

  // Two more models, from the panel generated from the registry.
  for (const name of ['ward', 'phong']) {
    await page.selectOption('#add-model', name);
    await page.click('#add');
    await page.waitForSelector(`.card[data-model="${name}"]`);
  }
  check(await page.locator('.card').count() === 3, 'two models picked (ggx, ward, phong shown together)');
  await page.waitForTimeout(800);
  const before = await page.evaluate(() => ['polar', 'albedo', 'slice'].map((id) => document.getElementById(id).toDataURL()));

  // Move the active model's (phong's) first slider, as a user drags it: 30 steps, 80 ms apart.
  const slider = page.locator('.card.active input[type=range]').first();
  const param = await slider.getAttribute('data-param');
  await page.evaluate(() => { window.gonioStats.plotLatencies.length = 0; window.gonioStats.plotParts.length = 0; });
  for (let k = 0; k < 30; k++) {
    await slider.evaluate((el, k) => {
      el.value = +el.min + ((+el.max - +el.min) * (0.3 + 0.4 * Math.abs(Math.sin(k / 5))));
      el.dispatchEvent(new Event('input', { bubbles: true }));
    }, k);
    await page.waitForTimeout(80);
  }
  await page.waitForTimeout(1200);
  const lat = await page.evaluate(() => window.gonioStats.plotLatencies.slice());
  const parts = await page.evaluate(() => window.gonioStats.plotParts.slice());
  const after = await page.evaluate(() => ['polar', 'albedo', 'slice'].map((id) => document.getElementById(id).toDataURL()));
  check(after[0] !== before[0] && after[1] !== before[1] && after[2] !== before[2], `moving phong's '${param}' slider redraws the polar, albedo and slice plots`);
  check(lat.length >= 25, `latency recorded for ${lat.length} of 30 slider moves`);
  const plot95 = p95(lat);
  console.log(`2D plot redraw after a slider move: median ${median(lat).toFixed(1)} ms, p95 ${plot95.toFixed(1)} ms, max ${Math.max(...lat).toFixed(1)} ms (${lat.length} moves); of which the /api/views request: median ${median(parts.map((p) => p.request)).toFixed(1)} ms, drawing the 2D plots: median ${median(parts.map((p) => p.draw)).toFixed(1)} ms`);
  console.log('slowest moves (total/request/draw ms): ' + parts.sort((a, b) => b.total - a.total).slice(0, 4).map((p) => [p.total, p.request, p.draw].map((x) => x.toFixed(0)).join('/')).join(', '));

  // Hovering the polar plot off the mirror direction: the read-out's value equals `gonio eval`
  // with the same model and directions.
  const pbox = await page.locator('#polar').boundingBox();
  await page.waitForTimeout(300);
  await page.mouse.move(pbox.x + 260 + 40, pbox.y + 280 - 200);
  await page.waitForFunction(() => /θo = /.test(document.getElementById('readout').textContent) && document.getElementById('readout').textContent.includes('phong:'));
  const ro = await page.evaluate(() => { const r = document.getElementById('readout'); return { text: r.textContent, wi: r.dataset.wi, wo: r.dataset.wo }; });
  const lines = ro.text.split('\n');
  let nonzero = 0;
  for (let i = 1; i + 1 < lines.length; i += 2) {
    const shown = lines[i + 1].match(/ρ = (\S+) (\S+) (\S+)/).slice(1).map(Number);
    const cli = JSON.parse(execFileSync(gonio, ['eval', ...evalArgs(lines[i]), '--wi', ro.wi, '--wo', ro.wo, '--json']).toString());
    check(cli.brdf.every((v, c) => v === shown[c]), `the read-out ρ of ${lines[i]} at wi=${ro.wi}, wo=${ro.wo} (${shown.join(' ')}) equals gonio eval's (${cli.brdf.join(' ')})`);
    nonzero += shown.some((v) => v > 0);
  }
  check(nonzero >= 2, `${nonzero} of the read-out values are non-zero`);
  await page.screenshot({ path: join(shots, '1-three-models.png'), fullPage: true });

  // The MERL file written by `gonio measure`, opened from the data folder.
  await page.selectOption('#data-file', 'gold.binary');
  await page.click('#open-file');
  await page.waitForSelector('.card.active[data-model="merl"]');
  check(true, 'the MERL file written by gonio measure opens as a model');

  // The lit sphere: first frames after light drags, each timed from request to drawn frame.
  await page.evaluate(() => { window.gonioStats.litFirstFrame.length = 0; });
  await page.locator('#sphere').scrollIntoViewIfNeeded();
  const box = await page.locator('#sphere').boundingBox();
  // Twenty moves, so that the p95 is the second slowest rather than the slowest of a few.
  const MOVES = 20;
  const lights = [];
  for (let k = 0; k < MOVES; k++) {
    await page.mouse.click(box.x + box.width * (0.25 + 0.025 * k), box.y + box.height * (0.3 + 0.1 * (k % 2)));
    await page.waitForTimeout(700);
    lights.push(await page.evaluate(() => location.hash.match(/light=([^&]+)/)[1]));
  }
  await page.waitForTimeout(1500);
  check(new Set(lights).size === MOVES, 'each click on the sphere moves the light (' + decodeURIComponent(lights[0]) + ' … ' + decodeURIComponent(lights[MOVES - 1]) + ')');
  const lit = await page.evaluate((n) => window.gonioStats.litFirstFrame.slice(-n), MOVES);
  const lit95 = p95(lit);
  const litPixels = await page.evaluate(() => {
    const c = document.getElementById('sphere'), d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let bright = 0;
    for (let i = 0; i < d.length; i += 4) if (d[i] + d[i + 1] + d[i + 2] > 60) bright++;
    return { bright, spp: +c.dataset.spp };
  });
  check(litPixels.bright > 5000 && litPixels.spp >= 2, `the lit sphere arrives and refines (${litPixels.bright} lit pixels, ${litPixels.spp} spp)`);
  console.log(`first lit-sphere frame (256×256): median ${median(lit).toFixed(1)} ms, p95 ${lit95.toFixed(1)} ms over ${lit.length} light moves`);

  // The check panel of the measured model.
  await page.waitForFunction(() => !/checking/.test(document.getElementById('check-info').textContent) && document.querySelectorAll('#findings tr').length === 6, null, { timeout: 30000 });
  const findings = await page.evaluate(() => [...document.querySelectorAll('#findings tr')].map((r) => r.textContent));
  const chi = await page.evaluate(() => document.getElementById('chi-p').textContent);
  check(findings.some((f) => f.includes('reciprocity')) && findings.some((f) => f.includes('energy')) && /p = /.test(chi), `the check panel reads: ${findings.map((f) => f.slice(0, 60)).join(' | ')}; χ²: ${chi}`);

  // Fit a model to the measured data and show the residual.
  await page.selectOption('#fit-model', 'ggx');
  await page.click('#fit');
  await page.waitForFunction(() => /error/.test(document.getElementById('fit-msg').textContent) && !document.getElementById('residual').hidden, null, { timeout: 30000 });
  const fitMsg = await page.evaluate(() => document.getElementById('fit-msg').textContent);
  check(/alpha 0\.19|alpha 0\.2/.test(fitMsg), `gonio fit recovers the measured ggx roughness: ${fitMsg}`);
  await page.waitForTimeout(1500);
  const commands = await page.evaluate(() => document.getElementById('commands').textContent);
  check(commands.includes('gonio eval merl') && commands.includes('gonio plot merl') && commands.includes('gonio compare'), 'copy as command gives the eval, plot and render lines');
  await page.screenshot({ path: join(shots, '2-measured-and-fit.png'), fullPage: true });

  // The page state is in the URL: a second tab opened on it shows the same models.
  const tab = await browser.newPage({ viewport: { width: 1440, height: 900 } });
  tab.on('console', (m) => { if (m.type() === 'error') errors.push('tab 2: ' + m.text()); });
  await tab.goto(page.url());
  await tab.waitForFunction(() => window.gonioReady && window.gonioStats.plotLatencies.length > 0);
  check(await tab.locator('.card').count() === await page.locator('.card').count(), 'a second tab opened on the URL shows the same models');
  await tab.close();

  check(errors.length === 0, 'no console errors' + (errors.length ? ': ' + errors.join(' / ') : ''));
  console.log(`LATENCY plot-redraw p95 ${plot95.toFixed(1)} ms (target ≤ ${PLOT_P95_MS}); lit first frame p95 ${lit95.toFixed(1)} ms (target ≤ ${LIT_FIRST_MS})`);
  check(plot95 <= PLOT_P95_MS, `2D plots redraw within ${PLOT_P95_MS} ms (p95)`);
  check(lit95 <= LIT_FIRST_MS, `the first lit-sphere frame arrives within ${LIT_FIRST_MS} ms (p95)`);
  console.log('screenshots in ' + shots);
} finally {
  await browser.close();
  server.kill();
  rmSync(data, { recursive: true, force: true });
}
