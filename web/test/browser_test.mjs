// Opens an iilfm HTML report in real headless Chromium and checks it:
//   node browser_test.mjs REPORT.html RESULT.json SCREENSHOT.png [CHROMIUM]
// - the page loads with no console error and no uncaught exception,
// - the WebGL canvas rendered pixels other than the background (points, outlines),
// - the marker table lists exactly the ids of RESULT.json (`iilfm detect --json` of the same run),
// - the intensity image decoded.
// Writes a screenshot of the page to SCREENSHOT.png and prints its path.
import {readFileSync} from 'node:fs';

import {checks, drawnPixels, openReport} from './browser.mjs';

const [report, resultJson, screenshot, executable = '/usr/bin/chromium'] = process.argv.slice(2);
if (!report || !resultJson || !screenshot) {
  console.error('usage: node browser_test.mjs REPORT.html RESULT.json SCREENSHOT.png [CHROMIUM]');
  process.exit(2);
}
const expected = JSON.parse(readFileSync(resultJson, 'utf8')).markers.map((m) => `${m.family}/${m.id}`);

const {check, failures} = checks();
const {browser, page, errors} = await openReport(report, executable);
try {
  const canvas = await drawnPixels(page, '#view canvas');
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
