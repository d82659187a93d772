// Open a page written by `brdffit fit --report` in headless Chromium and
// check what a reader sees (test export_report_browser):
//
//   node view_report.mjs MODULE_DIR CHROMIUM REPORT.html SCREENSHOT.png HEADING...
//
// MODULE_DIR is the node_modules folder holding `playwright-core`; CHROMIUM
// the browser. The page is opened from its file with the network switched
// off (it must stand alone). Fails (exit 1) on any console error, page
// error or request the page makes; when a HEADING (an <h2> text) is
// missing; when an image is not decoded or is blank (fewer than 16
// distinct colours when drawn); or when a table is empty. Writes a
// screenshot of the whole page. Exit 2 when the browser cannot be started.
import { createRequire } from 'module';
import fs from 'fs';
import os from 'os';
import path from 'path';

const [moduleDir, chromium, report, screenshot, ...headings] = process.argv.slice(2);
if (!moduleDir || !chromium || !report || !screenshot) {
    console.error('usage: node view_report.mjs MODULE_DIR CHROMIUM REPORT.html SCREENSHOT.png HEADING...');
    process.exit(1);
}
const require = createRequire(path.join(moduleDir, 'index.js'));

// What the page shows, measured inside it.
function inspect() {
    const images = [...document.images].map((img) => {
        const c = document.createElement('canvas');
        c.width = img.naturalWidth;
        c.height = img.naturalHeight;
        let colours = 0;
        if (img.complete && img.naturalWidth > 0) {
            const g = c.getContext('2d');
            g.drawImage(img, 0, 0);
            const d = g.getImageData(0, 0, c.width, c.height).data, seen = new Set();
            for (let i = 0; i < d.length && seen.size < 1000; i += 4 * 7)
                seen.add((d[i] << 16) | (d[i + 1] << 8) | d[i + 2]);
            colours = seen.size;
        }
        return { alt: img.alt, width: img.naturalWidth, height: img.naturalHeight, colours };
    });
    const tables = [...document.querySelectorAll('table')].map((t) => t.rows.length);
    const headings = [...document.querySelectorAll('h2')].map((h) => h.textContent.trim());
    return { images, tables, headings, title: document.title };
}

async function main() {
    const { chromium: pw } = require('playwright-core');
    const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'brdffit-report-'));
    let context;
    try {
        context = await pw.launchPersistentContext(profile, {
            executablePath: chromium, headless: true, offline: true,
            args: ['--headless', '--no-sandbox', '--disable-gpu', '--no-first-run',
                   '--disable-background-networking', '--disable-component-update', '--disable-sync'] });
    } catch (e) {
        console.error(`cannot start ${chromium}: ${e.message}`);
        fs.rmSync(profile, { recursive: true, force: true });
        return 2;
    }
    const problems = [];
    try {
        const page = await context.newPage();
        const url = 'file://' + path.resolve(report);
        page.on('console', (m) => { if (m.type() === 'error') problems.push(`console error: ${m.text()}`); });
        page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
        page.on('request', (r) => {
            if (r.url() !== url && !r.url().startsWith('data:')) problems.push(`request: ${r.url()}`);
        });
        await page.setViewportSize({ width: 1400, height: 900 });
        await page.goto(url, { waitUntil: 'load' });
        const seen = await page.evaluate(inspect);
        await page.screenshot({ path: screenshot, fullPage: true });
        console.log(`${report}: "${seen.title}", headings ${JSON.stringify(seen.headings)}, ` +
                    `tables of ${JSON.stringify(seen.tables)} rows, images ${JSON.stringify(seen.images)}`);
        for (const h of headings)
            if (!seen.headings.includes(h)) problems.push(`no heading "${h}"`);
        if (seen.images.length === 0) problems.push('no image');
        for (const img of seen.images)
            if (img.width === 0 || img.colours < 16)
                problems.push(`image "${img.alt}" not shown (${img.width} x ${img.height}, ${img.colours} colours)`);
        if (seen.tables.length === 0 || seen.tables.some((n) => n < 2)) problems.push('an empty table');
    } catch (e) {
        problems.push(`the page failed: ${e.message}`);
    } finally {
        await context.close();
        fs.rmSync(profile, { recursive: true, force: true });
    }
    for (const p of problems) console.log(`FAILS: ${p}`);
    return problems.length === 0 ? 0 : 1;
}

process.exit(await main());
