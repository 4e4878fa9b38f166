// Opens OUT/report.html in Debian's headless chromium (driven by playwright-core) at a 1280 px
// wide window and checks what a person would see, over the whole page height:
//   - the title, and no script error;
//   - nothing wider than the window (a figure cut off at the right edge);
//   - every plot loaded, and a full-page screenshot as tall as the page (nothing cut off below);
//   - the 3D view drew: its canvas, cut from that screenshot, has non-blank pixels.
// Usage: node check-report.mjs OUT/report.html SCREENSHOT.png
import { createRequire } from 'node:module';
import { fileURLToPath, pathToFileURL } from 'node:url';
import path from 'node:path';
import fs from 'node:fs';

const here = path.dirname(fileURLToPath(import.meta.url));
const require = createRequire(path.join(here, '..', 'apps', 'report', 'package.json'));
const { chromium } = require('playwright-core');
const { PNG } = require('pngjs');

const [page_file, shot_file] = process.argv.slice(2);
const WIDTH = 1280;

function fail(why) {
  console.error(`check-report: ${page_file}: ${why}`);
  process.exit(1);
}

// Share of the pixels inside `box` (CSS px) that differ from white.
function inked(png, box, scale) {
  let ink = 0, all = 0;
  const x0 = Math.round(box.x * scale), y0 = Math.round(box.y * scale);
  const x1 = Math.min(png.width, Math.round((box.x + box.width) * scale));
  const y1 = Math.min(png.height, Math.round((box.y + box.height) * scale));
  for (let y = y0; y < y1; ++y) {
    for (let x = x0; x < x1; ++x) {
      const i = 4 * (y * png.width + x);
      ++all;
      if (png.data[i] < 235 || png.data[i + 1] < 235 || png.data[i + 2] < 235) ++ink;
    }
  }
  return all ? ink / all : 0;
}

const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium',
  args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
         '--disable-component-update', '--disable-sync', '--enable-unsafe-swiftshader'],
});
try {
  const page = await browser.newPage({ viewport: { width: WIDTH, height: 900 } });
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  await page.goto(pathToFileURL(path.resolve(page_file)).href, { waitUntil: 'load' });
  await page.waitForFunction(() => window.cleanmapViewer !== undefined || !document.getElementById('map3d'),
                             null, { timeout: 30000 }).catch(() => {});
  const facts = await page.evaluate(() => ({
    title: document.querySelector('h1')?.textContent ?? '',
    scrollWidth: document.documentElement.scrollWidth,
    height: document.documentElement.scrollHeight,
    images: [...document.images].map((im) => ({ alt: im.alt, ok: im.complete && im.naturalWidth > 0,
                                               right: im.getBoundingClientRect().right })),
    viewer: window.cleanmapViewer ?? null,
    hasView: !!document.getElementById('map3d'),
    canvas: (() => {
      const c = document.querySelector('#map3d canvas');
      if (!c) return null;
      const r = c.getBoundingClientRect();
      return { x: r.x + window.scrollX, y: r.y + window.scrollY, width: r.width, height: r.height };
    })(),
  }));
  if (!facts.title.includes('cleanmap report')) fail('no "cleanmap report" title');
  if (errors.length) fail(`script errors: ${errors.join('; ')}`);
  if (facts.scrollWidth > WIDTH) fail(`the page is ${facts.scrollWidth} px wide in a ${WIDTH} px window (cut off)`);
  if (facts.images.length < 2) fail(`${facts.images.length} plots (the map and the per-scan plot at least)`);
  for (const im of facts.images) {
    if (!im.ok) fail(`plot ${im.alt} did not load`);
    if (im.right > WIDTH) fail(`plot ${im.alt} reaches ${Math.round(im.right)} px, past the ${WIDTH} px window`);
  }
  await page.screenshot({ path: shot_file, fullPage: true });
  const png = PNG.sync.read(fs.readFileSync(shot_file));
  const scale = png.width / WIDTH;
  if (Math.abs(png.height / scale - facts.height) > 2) {
    fail(`the screenshot is ${png.height / scale} px tall, the page ${facts.height} px`);
  }
  let view = 'no 3D view';
  if (facts.hasView) {
    if (!facts.viewer?.drawn || !facts.canvas) fail(`the 3D view did not draw (${JSON.stringify(facts.viewer)})`);
    const share = inked(png, facts.canvas, scale);
    if (share < 0.01) fail(`the 3D view's canvas is blank (${(100 * share).toFixed(2)}% of its pixels drawn)`);
    view = `3D view drew ${facts.viewer.staticPoints} + ${facts.viewer.removedPoints} points, ` +
           `${(100 * share).toFixed(1)}% of its canvas inked`;
  }
  console.log(`check-report: ${page_file} renders: ${facts.images.length} plots, page ${facts.height} px ` +
              `tall, all within ${WIDTH} px; ${view}; screenshot ${shot_file}`);
} finally {
  await browser.close();
}
