// Opens a geardyn report in headless Chromium (Debian's /usr/bin/chromium) as a reader would:
// the top index and every preset page it links. On each page it scrolls to the bottom so that
// lazily loaded figures load, then fails on a figure that does not load, a console error, a
// failed request, or (on a preset page) a missing claims table. One full-page screenshot per
// page goes to SCREENS (default: beside each page, `screenshot.png`).
//
// Usage: node check.mjs REPORT_DIR_OR_INDEX [SCREENS_DIR]
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';

const arg = path.resolve(process.argv[2] ?? 'target/report-check');
const root = fs.statSync(arg).isDirectory() ? path.join(arg, 'index.html') : arg;
const screens = process.argv[3] ? path.resolve(process.argv[3]) : null;
if (!fs.existsSync(root)) {
  console.error(`no report page at ${root}`);
  process.exit(2);
}
if (screens) fs.mkdirSync(screens, { recursive: true });

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
         '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});

// Checks one page; returns its problems and the preset pages it links.
async function check(file, mustBePreset) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
  const problems = [];
  page.on('console', (m) => { if (m.type() === 'error') problems.push(`console: ${m.text()}`); });
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  page.on('requestfailed', (r) => problems.push(`request failed: ${r.url()}`));
  await page.goto('file://' + file, { waitUntil: 'load' });
  // scroll a screen at a time so that every lazy image enters the viewport and loads
  // (the page grows as figures load: its height is read again at every step)
  for (let y = 0; y < (await page.evaluate(() => document.body.scrollHeight)); y += 700) {
    await page.evaluate((yy) => window.scrollTo(0, yy), y);
    await page.waitForTimeout(60);
  }
  await page.evaluate(() => window.scrollTo(0, document.body.scrollHeight));
  await page.waitForTimeout(200);
  try {
    await page.waitForFunction(() => [...document.images].every((i) => i.complete), null, { timeout: 20000 });
  } catch {
    problems.push('images still loading after 20 s');
  }
  const imgs = await page.$$eval('img', (els) => els.map((e) => ({ src: e.getAttribute('src'), ok: e.complete && e.naturalWidth > 0 })));
  for (const b of imgs.filter((i) => !i.ok)) problems.push(`broken image: ${b.src}`);
  const links = await page.$$eval('a[href]', (as) => as.map((a) => a.getAttribute('href')));
  for (const href of links) {
    if (/^(https?:|mailto:|#)/.test(href)) continue;
    const target = path.resolve(path.dirname(file), decodeURIComponent(href.split('#')[0]));
    if (!fs.existsSync(target)) problems.push(`broken link: ${href}`);
  }
  const presetLinks = links.filter((h) => /^[^/:#]+\/index\.html$/.test(h));
  // the top index links preset pages and has no claims of its own
  const isIndex = !mustBePreset && presetLinks.length > 0;
  let claims = 0;
  if (!isIndex) {
    claims = await page.$$eval('#claims-table tr', (rows) => Math.max(rows.length - 1, 0));
    if (claims === 0) problems.push('no claims table (#claims-table) with rows');
    if (imgs.length === 0) problems.push('no figure on the page');
  }
  // a table or figure wider than the window makes the whole page scroll sideways
  const wide = await page.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
  if (wide > 1) problems.push(`page ${wide} px wider than the window (a table or figure overflows)`);
  const sections = await page.$$eval('h2', (h) => h.length);
  await page.evaluate(() => window.scrollTo(0, 0));
  const shot = screens
    ? path.join(screens, `${path.basename(path.dirname(file))}-${path.basename(file, '.html')}.png`)
    : path.join(path.dirname(file), 'screenshot.png');
  await page.screenshot({ path: shot, fullPage: !isIndex });
  await page.close();
  console.log(`${path.relative(process.cwd(), file)}: ${imgs.length} images, ${sections} sections, ${claims} claim rows, ${problems.length} problems; screenshot ${path.relative(process.cwd(), shot)}`);
  const presets = isIndex ? presetLinks.map((h) => path.resolve(path.dirname(file), h)) : [];
  return { problems, presets };
}

// the top index links the preset pages; a preset page given directly is checked alone
let failed = 0;
const top = await check(root, false);
const pages = top.presets;
for (const p of top.problems) { console.log(`  ${p}`); failed += 1; }
for (const p of pages) {
  const r = await check(p, false);
  for (const q of r.problems) { console.log(`  ${q}`); failed += 1; }
}
await browser.close();
console.log(failed === 0 ? `page check passed (${pages.length || 1} preset pages)` : `page check FAILED: ${failed} problems`);
process.exit(failed === 0 ? 0 : 1);
