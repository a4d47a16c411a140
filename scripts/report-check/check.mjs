// Opens a geardyn report in headless Chromium (Debian's /usr/bin/chromium) as a reader would,
// and fails if an image does not load, a console error appears, or the page lacks its parts.
import { chromium } from 'playwright-core';
import path from 'node:path';

const page_path = path.resolve(process.argv[2] ?? 'target/report-check/index.html');
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
         '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
const errors = [];
page.on('console', (m) => { if (m.type() === 'error') errors.push(`console: ${m.text()}`); });
page.on('pageerror', (e) => errors.push(`page: ${e.message}`));
page.on('requestfailed', (r) => errors.push(`request failed: ${r.url()}`));
await page.goto('file://' + page_path, { waitUntil: 'load' });
const imgs = await page.$$eval('img', (els) => els.map((e) => ({ src: e.getAttribute('src'), ok: e.complete && e.naturalWidth > 0 })));
const broken = imgs.filter((i) => !i.ok);
const claims = await page.$$eval('#claims + table tr', (rows) => rows.length);
const sections = await page.$$eval('h2', (h) => h.length);
await page.screenshot({ path: path.join(path.dirname(page_path), 'screenshot.png'), fullPage: false });
await browser.close();
console.log(`${imgs.length} images (${broken.length} broken), ${sections} sections, ${claims} claim rows, ${errors.length} errors`);
for (const b of broken) console.log(`broken image: ${b.src}`);
for (const e of errors) console.log(e);
if (imgs.length === 0 || broken.length > 0 || errors.length > 0 || sections < 3) process.exit(1);
