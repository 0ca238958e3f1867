// What the browser tests share: open a report in real headless Chromium, count drawn canvas
// pixels, and record checks.
import {pathToFileURL} from 'node:url';
import {chromium} from 'playwright-core';

export function checks() {
  const failures = [];
  const check = (ok, what) => {
    console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
    if (!ok) failures.push(what);
  };
  return {check, failures};
}

// Opens `report` and waits for the viewer to finish; `errors` collects console errors and
// uncaught exceptions from then on.
export async function openReport(report, executable) {
  // Headless Chromium has no GPU here: WebGL runs on SwiftShader, which must be allowed explicitly.
  const browser = await chromium.launch({
    executablePath: executable,
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  const page = await browser.newPage({viewport: {width: 1280, height: 1000}});
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(`console: ${m.text()}`); });
  page.on('pageerror', (e) => errors.push(`exception: ${e.message}`));
  await page.goto(pathToFileURL(report).href, {waitUntil: 'load'});
  await page.waitForFunction(() => window.iilfmReport && window.iilfmReport.ready,
                             null, {timeout: 60000});
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => r())));
  return {browser, page, errors};
}

// Pixels of the WebGL canvas in `selector` that differ from the clear colour (0x10141c), or null
// when there is no canvas.
export function drawnPixels(page, selector) {
  return page.evaluate((selector) => {
    const gl = document.querySelector(selector);
    if (!gl) return null;
    const c = document.createElement('canvas');
    c.width = gl.width;
    c.height = gl.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(gl, 0, 0);
    const px = ctx.getImageData(0, 0, c.width, c.height).data;
    let drawn = 0;
    for (let i = 0; i < px.length; i += 4) {
      const d = Math.abs(px[i] - 0x10) + Math.abs(px[i + 1] - 0x14) + Math.abs(px[i + 2] - 0x1c);
      if (d > 24) ++drawn;
    }
    return {drawn, total: px.length / 4};
  }, selector);
}
