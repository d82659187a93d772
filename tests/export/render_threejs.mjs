// Render exported glTF materials with three.js, or exported MaterialX
// documents with MaterialX's own shader generator, in headless Chromium and
// compare them with the library's own sphere pictures of the fitted models
// (tests export_threejs_render and export_mtlx_render):
//
//   node render_threejs.mjs MODULE_DIR CHROMIUM SPHERE_PICTURE OUT_DIR MIN_PSNR JOB...
//
// MODULE_DIR is the node_modules folder holding `three` and
// `playwright-core` (and `@needle-tools/materialx` for .mtlx jobs);
// CHROMIUM the browser (/usr/bin/chromium);
// SPHERE_PICTURE the test program that draws the library's picture
// (sphere_picture.c); JOB is LABEL=FIT.json,ASSET.gltf[,SHIPPED_MIN] (a
// fit's JSON record, its --gltf export, and the least PSNR of three.js as
// shipped, MIN_PSNR unless given). For every job and light polar angle (30
// and 60 deg, azimuth 0) it draws both pictures at SIZE x SIZE, encodes
// three.js's linear radiance with the library's rule (clamp to [0, 1],
// power 1 / 2.2, round to 8 bits) and prints the PSNR over the sphere's
// pixels of three.js as shipped and with its three departures from the
// glTF formulas switched off (render_threejs.html says which). A job whose
// asset is a .mtlx document (FILE.mtlx, or FILE.mtlx#SHADER to pick the
// material of that surface shader, open_pbr_surface or standard_surface,
// from a document of both) is rendered once, by the shaders MaterialX
// generates for it (render_mtlx.html), and its PSNR is held to SHIPPED_MIN
// (MIN_PSNR unless given); the jobs of one run are all glTF or all
// MaterialX. It writes
// OUT_DIR/LABEL-THETA.png: library | three.js as shipped | 8 x |difference|.
// Exits 0 when every spec-exact PSNR reaches MIN_PSNR and every as-shipped
// one its job's minimum, both over 99 % of the sphere's pixels; 1 when one
// does not or a page fails (console errors included); 2 when the browser
// cannot be started.
import { createRequire } from 'module';
import { execFileSync } from 'child_process';
import fs from 'fs';
import http from 'http';
import os from 'os';
import path from 'path';
import zlib from 'zlib';
import { fileURLToPath } from 'url';

const SIZE = 256;
const LIGHTS = [30, 60];
const EXPOSURE = Math.PI; // the library's default sphere exposure
const GAMMA = 2.2;        // and its default gamma
const HERE = path.dirname(fileURLToPath(import.meta.url));

// bf_image_encode() of lib/image/options.c.
function encode(v) {
    if (!(v > 0)) return 0;
    if (v >= 1) return 255;
    return Math.floor(255 * Math.pow(v, 1 / GAMMA) + 0.5);
}

function readPpm(file) {
    const b = fs.readFileSync(file);
    const head = b.subarray(0, 64).toString('latin1').match(/^P6\s+(\d+)\s+(\d+)\s+255\s/);
    if (!head) throw new Error(`${file}: not a binary PPM`);
    return { w: +head[1], h: +head[2], rgb: b.subarray(head[0].length) };
}

function crc32(buf) {
    let c, crc = 0xffffffff;
    for (let n = 0; n < buf.length; n++) {
        c = (crc ^ buf[n]) & 0xff;
        for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
        crc = (crc >>> 8) ^ c;
    }
    return (crc ^ 0xffffffff) >>> 0;
}

function writePng(file, w, h, rgb) {
    const raw = Buffer.alloc((3 * w + 1) * h);
    for (let y = 0; y < h; y++) rgb.copy(raw, y * (3 * w + 1) + 1, 3 * w * y, 3 * w * (y + 1));
    const chunk = (type, data) => {
        const len = Buffer.alloc(4), crc = Buffer.alloc(4), td = Buffer.concat([Buffer.from(type), data]);
        len.writeUInt32BE(data.length);
        crc.writeUInt32BE(crc32(td));
        return Buffer.concat([len, td, crc]);
    };
    const ihdr = Buffer.alloc(13);
    ihdr.writeUInt32BE(w, 0);
    ihdr.writeUInt32BE(h, 4);
    ihdr[8] = 8;
    ihdr[9] = 2;
    fs.writeFileSync(file, Buffer.concat([Buffer.from([137, 80, 78, 71, 13, 10, 26, 10]),
        chunk('IHDR', ihdr), chunk('IDAT', zlib.deflateSync(raw)), chunk('IEND', Buffer.alloc(0))]));
}

// Serve the page, three.js and the assets from 127.0.0.1 (module scripts
// do not load from file:// URLs).
function serve(moduleDir) {
    const types = { '.html': 'text/html', '.js': 'text/javascript', '.gltf': 'model/gltf+json',
                    '.wasm': 'application/wasm', '.mtlx': 'application/xml' };
    const server = http.createServer((req, res) => {
        const url = decodeURIComponent(new URL(req.url, 'http://x').pathname);
        let file = null;
        if (url === '/favicon.ico') {
            res.writeHead(204);
            res.end();
            return;
        }
        if (url === '/') file = path.join(HERE, 'render_threejs.html');
        else if (url === '/mtlx.html') file = path.join(HERE, 'render_mtlx.html');
        else if (url.startsWith('/three/')) file = path.join(moduleDir, url);
        else if (url.startsWith('/materialx/'))
            file = path.join(moduleDir, '@needle-tools', url);
        else if (url.startsWith('/asset/')) file = url.slice('/asset'.length);
        if (!file || url.includes('..') || !fs.existsSync(file)) {
            res.writeHead(404);
            res.end();
            return;
        }
        res.writeHead(200, { 'Content-Type': types[path.extname(file)] || 'application/octet-stream' });
        fs.createReadStream(file).pipe(res);
    });
    return new Promise((ok) => server.listen(0, '127.0.0.1', () => ok(server)));
}

async function launch(require, chromium) {
    const { chromium: pw } = require('playwright-core');
    const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'brdffit-chromium-'));
    const args = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
                  '--disable-background-networking', '--disable-component-update', '--disable-sync',
                  '--use-angle=swiftshader', '--enable-unsafe-swiftshader'];
    const context = await pw.launchPersistentContext(profile, { executablePath: chromium, headless: true,
                                                               args });
    return { context, profile };
}

// The library's picture of the fitted model for light polar angle theta.
function libraryPicture(exe, fit, theta, out) {
    const args = [fit.model, String(fit.channels), String(SIZE), String(theta), '0', out];
    for (const [name, v] of Object.entries(fit.params))
        args.push(`${name}=${Array.isArray(v) ? v.map((x) => x.toPrecision(17)).join(',') : v.toPrecision(17)}`);
    execFileSync(exe, args);
    return readPpm(out);
}

// PSNR over the pixels whose centre lies on the sphere (the library's
// rule) and which three.js covered; returns the figure, the pixel counts and
// the encoded three.js picture.
function compare(lib, linear) {
    const three = Buffer.alloc(3 * SIZE * SIZE, 48);
    let se = 0, n = 0, disk = 0;
    for (let y = 0; y < SIZE; y++) {
        const w = 1 - (2 * y + 1) / SIZE, row = SIZE - 1 - y; // GL rows run bottom-up
        for (let x = 0; x < SIZE; x++) {
            const u = (2 * x + 1) / SIZE - 1, k = 4 * (row * SIZE + x), o = 3 * (y * SIZE + x);
            const covered = linear[k + 3] > 0.5;
            if (covered) for (let c = 0; c < 3; c++) three[o + c] = encode(linear[k + c]);
            if (u * u + w * w > 1) continue;
            disk++;
            if (!covered) continue;
            n++;
            for (let c = 0; c < 3; c++) se += (three[o + c] - lib.rgb[o + c]) ** 2;
        }
    }
    const mse = se / (3 * n);
    return { psnr: mse > 0 ? 10 * Math.log10(255 * 255 / mse) : Infinity, n, disk, three };
}

function sheet(lib, three) {
    const w = 3 * SIZE, out = Buffer.alloc(3 * w * SIZE);
    for (let y = 0; y < SIZE; y++)
        for (let x = 0; x < SIZE; x++)
            for (let c = 0; c < 3; c++) {
                const i = 3 * (y * SIZE + x) + c, a = lib.rgb[i], b = three[i];
                out[3 * (y * w + x) + c] = a;
                out[3 * (y * w + SIZE + x) + c] = b;
                out[3 * (y * w + 2 * SIZE + x) + c] = Math.min(255, 8 * Math.abs(a - b));
            }
    return out;
}

function isMtlx(job) {
    return /\.mtlx(#|$)/.test(job.gltf);
}

// A MaterialX job: one picture per light, held to the job's minimum.
async function renderMtlxJob(page, job, fit, exe, outDir, minPsnr) {
    let ok = true;
    for (const theta of LIGHTS) {
        const lib = libraryPicture(exe, fit, theta, path.join(outDir, `${job.label}-${theta}.ppm`));
        const [file, shader] = job.gltf.split('#');
        const info = await page.evaluate(([u, m, s, t, e]) => window.renderMtlx(u, m, s, t, 0, e),
                                         [`/asset${path.resolve(file)}`, shader || null, SIZE, theta,
                                          EXPOSURE]);
        const bytes = Buffer.from(info.pixels, 'base64');
        const r = compare(lib, new Float32Array(bytes.buffer, bytes.byteOffset, bytes.length / 4));
        writePng(path.join(outDir, `${job.label}-${theta}.png`), 3 * SIZE, SIZE, sheet(lib, r.three));
        const min = job.min === undefined ? minPsnr : job.min;
        const pass = r.psnr >= min && r.n >= 0.99 * r.disk;
        ok = ok && pass;
        console.log(`${job.label} ${fit.model} light ${theta} deg: PSNR ${r.psnr.toFixed(2)} dB ` +
                    `over ${r.n} of ${r.disk} sphere pixels; ${info.loadedType} rendered by ` +
                    `${info.renderedType} (${info.pixelChars} characters)` +
                    `${pass ? '' : `; FAILS (needs >= ${min} dB over 99 % of the sphere)`}`);
    }
    return ok;
}

async function renderJob(page, job, exe, outDir, minPsnr) {
    const fit = JSON.parse(fs.readFileSync(job.json, 'utf8'));
    let ok = true;
    if (isMtlx(job)) return renderMtlxJob(page, job, fit, exe, outDir, minPsnr);
    for (const theta of LIGHTS) {
        const lib = libraryPicture(exe, fit, theta, path.join(outDir, `${job.label}-${theta}.ppm`));
        const figures = [];
        let shipped = null, info = null;
        for (const exact of [false, true]) {
            info = await page.evaluate(([u, s, t, e, x]) => window.renderGltf(u, s, t, 0, e, x),
                                       [`/asset${path.resolve(job.gltf)}`, SIZE, theta, EXPOSURE, exact]);
            const bytes = Buffer.from(info.pixels, 'base64');
            const r = compare(lib, new Float32Array(bytes.buffer, bytes.byteOffset, bytes.length / 4));
            figures.push(r);
            if (!exact) shipped = r;
        }
        writePng(path.join(outDir, `${job.label}-${theta}.png`), 3 * SIZE, SIZE, sheet(lib, shipped.three));
        const shippedMin = job.min === undefined ? minPsnr : job.min;
        const pass = shipped.psnr >= shippedMin && figures[1].psnr >= minPsnr &&
                     shipped.n >= 0.99 * shipped.disk;
        ok = ok && pass;
        console.log(`${job.label} ${fit.model} light ${theta} deg: PSNR ${shipped.psnr.toFixed(2)} dB ` +
                    `as shipped, ${figures[1].psnr.toFixed(2)} dB spec-exact, over ${shipped.n} of ` +
                    `${shipped.disk} sphere pixels; ${info.loadedType} rendered as ${info.renderedType}` +
                    `${pass ? '' : `; FAILS (needs >= ${shippedMin} dB as shipped and >= ${minPsnr} dB ` +
                                   'spec-exact over 99 % of the sphere)'}`);
    }
    return ok;
}

async function main() {
    const [moduleDir, chromium, exe, outDir, minPsnr, ...specs] = process.argv.slice(2);
    const require = createRequire(path.join(path.resolve(moduleDir), 'x.js'));
    const jobs = specs.map((s) => {
        const [label, files] = s.split('=');
        const [json, gltf, min] = files.split(',');
        return { label, json, gltf, min: min === undefined ? undefined : Number(min) };
    });
    const mtlx = jobs.filter(isMtlx).length;
    if (mtlx !== 0 && mtlx !== jobs.length) {
        console.error('the jobs of one run are all glTF or all MaterialX');
        return 2;
    }
    let browser;
    try {
        browser = await launch(require, chromium);
    } catch (e) {
        console.error(`cannot start ${chromium}: ${e.message || e}`);
        return 2;
    }
    const server = await serve(moduleDir);
    const errors = [];
    let ok = true;
    try {
        const page = await browser.context.newPage();
        page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
        page.on('pageerror', (e) => errors.push(e.message));
        await page.goto(`http://127.0.0.1:${server.address().port}/${mtlx ? 'mtlx.html' : ''}`);
        await page.waitForFunction(() => window.pageReady === true, null, { timeout: 60000 });
        const info = await page.evaluate(() => {
            const gl = document.createElement('canvas').getContext('webgl2');
            const d = gl && gl.getExtension('WEBGL_debug_renderer_info');
            return gl ? (d ? gl.getParameter(d.UNMASKED_RENDERER_WEBGL) : 'WebGL2') : null;
        });
        if (!info) throw new Error('no WebGL2 context in the headless browser');
        console.log(`WebGL2 renderer: ${info}`);
        for (const job of jobs) ok = (await renderJob(page, job, exe, outDir, Number(minPsnr))) && ok;
    } catch (e) {
        console.log(`page failed: ${e.message || e}`);
        ok = false;
    } finally {
        server.close();
        await browser.context.close();
        fs.rmSync(browser.profile, { recursive: true, force: true });
    }
    if (errors.length) {
        console.log(`console errors:\n${errors.join('\n')}`);
        ok = false;
    }
    return ok ? 0 : 1;
}

main().then((code) => process.exit(code));
