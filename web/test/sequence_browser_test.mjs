// Opens the HTML report of a recording in real headless Chromium and checks it against the JSON
// lines of the same run:
//   node sequence_browser_test.mjs REPORT.html RESULTS.jsonl MAP.yaml SCREENSHOT.png [CHROMIUM]
// - no console error and no uncaught exception,
// - the trajectory view and the frame view drew pixels, every map marker is outlined and those
//   detected in some frame are labelled,
// - the frames table has one row per JSON line, with its frame number and marker ids,
// - the x/y/z plots hold one point per frame with a pose,
// - the frame shown in full is the last one with markers, and its marker table lists its ids,
// - moving the slider selects that frame (detail table, highlighted row, redrawn trajectory view).
// Writes a screenshot of the page to SCREENSHOT.png.
import {readFileSync} from 'node:fs';

import {checks, drawnPixels, openReport} from './browser.mjs';

const [report, jsonl, mapYaml, screenshot, executable = '/usr/bin/chromium'] =
    process.argv.slice(2);
if (!report || !jsonl || !mapYaml || !screenshot) {
  console.error(
      'usage: node sequence_browser_test.mjs REPORT.html RESULTS.jsonl MAP.yaml SCREENSHOT.png ' +
      '[CHROMIUM]');
  process.exit(2);
}
const lines = readFileSync(jsonl, 'utf8').split('\n').filter((l) => l).map((l) => JSON.parse(l));
const keys = (line) => line.markers.map((m) => `${m.family}/${m.id}`);
const mapMarkers = (readFileSync(mapYaml, 'utf8').match(/^\s*-\s*family:/gm) || []).length;
const detected = new Set(lines.flatMap((l) => l.markers.filter((m) => m.in_map).map((m) => m.id)));
const posed = lines.filter((l) => l.pose).length;
const shown = lines.filter((l) => l.markers.length).pop();

const {check, failures} = checks();
const {browser, page, errors} = await openReport(report, executable);
try {
  check(lines.length > 2 && posed > 2 && posed < lines.length,
        `the recording has ${lines.length} frames, ${posed} with a pose`);
  const info = await page.$eval('#sequence-info', (e) => e.textContent);
  check(info.startsWith(`${lines.length} results`), `the summary counts the frames: "${info}"`);

  const trajectory = await drawnPixels(page, '#trajectory-view canvas');
  check(trajectory !== null, 'the page has a trajectory view');
  if (trajectory) {
    console.log(`     trajectory canvas: ${trajectory.drawn} of ${trajectory.total} pixels drawn`);
    check(trajectory.drawn > 0.002 * trajectory.total,
          'the trajectory view shows the path and the map (>0.2% of pixels drawn)');
  }
  const outlines = await page.evaluate(() => window.iilfmReport.mapOutlines);
  check(mapMarkers > 0 && outlines === mapMarkers, `every map marker is outlined (${outlines})`);
  const labels =
      await page.$$eval('.map-label', (ls) => ls.map((l) => Number(l.textContent.slice(1))));
  check(JSON.stringify(labels.sort((a, b) => a - b)) ===
            JSON.stringify([...detected].sort((a, b) => a - b)),
        `the map markers the recording detected are labelled (${labels.length})`);

  const rows = await page.$$eval('#frames tbody tr', (rs) => rs.map((r) => ({
                                                       frame: Number(r.dataset.frame),
                                                       ids: r.dataset.ids
                                                     })));
  check(rows.length === lines.length,
        `the frames table has one row per JSON line (${rows.length})`);
  check(rows.every((r, i) => lines[i] && r.frame === lines[i].frame &&
                             r.ids === keys(lines[i]).join(' ')),
        'every row has the frame number and the marker ids of its JSON line');

  const plotted = await page.$$eval('#plots svg', (plots) => plots.map(
      (p) => [...p.querySelectorAll('polyline')].reduce(
                 (n, l) => n + l.getAttribute('points').trim().split(/\s+/).length, 0) +
          p.querySelectorAll('circle').length));
  check(plotted.length === 3 && plotted.every((n) => n === posed),
        `the x, y and z plots hold one point per frame with a pose (${plotted.join(', ')})`);

  const shownFrame = await page.$eval('#shown-frame', (e) => Number(e.dataset.frame));
  check(shownFrame === shown.frame,
        `the frame shown in full is the last with markers (${shownFrame})`);
  const listed = await page.$$eval('#markers tbody tr',
                                   (rs) => rs.map((r) => `${r.dataset.family}/${r.dataset.id}`));
  check(JSON.stringify(listed) === JSON.stringify(keys(shown)),
        `its marker table lists its ids (${listed.length})`);
  const frameView = await drawnPixels(page, '#view canvas');
  check(frameView !== null && frameView.drawn > 0.01 * frameView.total,
        'the frame view shows the cloud (>1% of pixels drawn)');
  const image = await page.$eval('#overlay', (img) => img.complete && img.naturalWidth);
  check(image > 0, 'the intensity image with detections decoded');
  await page.screenshot({path: screenshot, fullPage: true});
  console.log(`screenshot: ${screenshot}`);

  // Select the first frame with the slider.
  const before = await page.$eval('#trajectory-view canvas', (c) => c.toDataURL());
  await page.$eval('#frame-slider', (s) => {
    s.value = 0;
    s.dispatchEvent(new Event('input'));
  });
  const detail = await page.$eval('#frame-selected tbody td', (td) => Number(td.textContent));
  check(detail === lines[0].frame, 'the slider selects frame 0 in the detail table');
  const selected =
      await page.$$eval('#frames tbody tr.selected', (rs) => rs.map((r) => r.rowIndex));
  check(JSON.stringify(selected) === '[1]', 'and highlights its row only');
  const after = await page.$eval('#trajectory-view canvas', (c) => c.toDataURL());
  check(before !== after, 'and redraws the trajectory view (LiDAR axes, detected markers)');
  check(errors.length === 0, `no console errors${errors.length ? ': ' + errors.join('; ') : ''}`);
} finally {
  await browser.close();
}
if (failures.length) {
  console.error(`${failures.length} check(s) failed`);
  process.exit(1);
}
