// Opens an iilfm HTML report in real headless Chromium and checks it:
//   node browser_test.mjs REPORT.html RESULT.json SCREENSHOT.png [CHROMIUM]
// - the page loads with no console error and no uncaught exception,
// - the WebGL canvas rendered pixels other than the background (points, outlines),
// - the marker table lists exactly the ids of RESULT.json (`iilfm detect --json` of the same run),
// - the intensity image decoded.
// Writes a screenshot of the page to SCREENSHOT.png and prints its path.
import {readFileSync} from 'node:fs';
import {pathToFileURL} from 'node:url';
import {chromium} from 'playwright-core';

const [report, resultJson, screenshot, executable = '/usr/bin/chromium'] = process.argv.slice(2);
if (!report || !resultJson || !screenshot) {
  console.error('usage: node browser_test.mjs REPORT.html RESULT.json SCREENSHOT.png [CHROMIUM]');
  process.exit(2);
}
const expected = JSON.parse(readFileSync(resultJson, 'utf8')).markers.map((m) => `${m.family}/${m.id}`);

const failures = [];
const check = (ok, what) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
};

// Headless Chromium has no GPU here: WebGL runs on SwiftShader, which must be allowed explicitly.
const browser = await chromium.launch({
  executablePath: executable,
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
try {
  const page = await browser.newPage({viewport: {width: 1280, height: 1000}});
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(`console: ${m.text()}`); });
  page.on('pageerror', (e) => errors.push(`exception: ${e.message}`));
  await page.goto(pathToFileURL(report).href, {waitUntil: 'load'});
  await page.waitForFunction(() => window.iilfmReport && window.iilfmReport.ready,
                             null, {timeout: 60000});
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => r())));

  // Pixels of the WebGL canvas that differ from the clear colour (0x10141c).
  const canvas = await page.evaluate(() => {
    const gl = document.querySelector('#view canvas');
    if (!gl) return null;
    const c = document.createElement('canvas');
    c.width = gl.width;
    c.height = gl.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(gl, 0, 0);
    const px = ctx.getImageData(0, 0, c.width, c.height).data;
    let drawn = 0;
    for (let i = 0; i < px.length; i += 4) {
      if (Math.abs(px[i] - 0x10) + Math.abs(px[i + 1] - 0x14) + Math.abs(px[i + 2] - 0x1c) > 24) ++drawn;
    }
    return {drawn, total: px.length / 4};
  });
  check(canvas !== null, 'the page has a WebGL canvas');
  if (canvas) {
    console.log(`     canvas: ${canvas.drawn} of ${canvas.total} pixels drawn`);
    check(canvas.drawn > 0.01 * canvas.total, 'the canvas shows the cloud (>1% of pixels drawn)');
  }
  const listed = await page.$$eval('#markers tbody tr',
                                   (rows) => rows.map((r) => `${r.dataset.family}/${r.dataset.id}`));
  console.log(`     marker table: ${listed.join(' ')}`);
  check(expected.length > 0, `the result has markers (${expected.length})`);
  check(JSON.stringify(listed) === JSON.stringify(expected),
        'the marker table lists the ids of the JSON result, in order');
  const labels = await page.$$eval('.marker-label', (ls) => ls.map((l) => l.textContent));
  check(labels.length === expected.length, '3-D view labels every marker');
  const image = await page.$eval('#overlay', (img) => img.complete && img.naturalWidth);
  check(image > 0, 'the intensity image with detections decoded');
  check(await page.$('#pose table, table#pose') !== null, 'the pose table is shown');
  await page.screenshot({path: screenshot, fullPage: true});
  console.log(`screenshot: ${screenshot}`);
  check(errors.length === 0, `no console errors${errors.length ? ': ' + errors.join('; ') : ''}`);
} finally {
  await browser.close();
}
if (failures.length) {
  console.error(`${failures.length} check(s) failed`);
  process.exit(1);
}
