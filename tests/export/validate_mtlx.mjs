// Load MaterialX documents with the MaterialX library itself (its
// WebAssembly build in npm @needle-tools/materialx) and check them:
//
//   node validate_mtlx.mjs MODULE_DIR FILE...
//
// MODULE_DIR is the node_modules folder that holds @needle-tools/materialx.
// For every file: read it, bind it to the standard data libraries,
// Document.validate(), resolve every node's node definition, and generate
// the ESSL shader of every surfacematerial. Exits 0 when every file
// passes, 1 when one fails, 2 when the library cannot be loaded.
import { createRequire } from 'module';
import fs from 'fs';
import path from 'path';

async function loadMaterialX(moduleDir) {
    const bin = path.resolve(moduleDir, '@needle-tools', 'materialx', 'bin');
    // The Emscripten loader is written for CommonJS and the browser: give it
    // the require and __dirname that an ES module lacks, and the name under
    // which the package ships its data file.
    globalThis.require = createRequire(import.meta.url);
    globalThis.__dirname = bin;
    const mod = await import(path.join(bin, 'JsMaterialXGenShader.js'));
    return mod.default({
        locateFile: (f) => path.join(bin, f.endsWith('.data') ? f + '.txt' : f),
        print: () => {},
    });
}

async function check(mx, gen, ctx, stdlib, file) {
    const doc = mx.createDocument();
    await mx.readFromXmlString(doc, fs.readFileSync(file, 'utf8'));
    doc.setDataLibrary(stdlib);
    const msg = {};
    if (!doc.validate(msg)) return `invalid: ${(msg.message || '').trim()}`;
    for (const node of doc.getNodes())
        if (!node.getNodeDef()) return `node ${node.getName()} (${node.getCategory()}) has no definition`;
    const materials = doc.getNodes().filter((n) => n.getCategory() === 'surfacematerial');
    if (materials.length === 0) return 'no renderable element';
    const shaders = [];
    for (const elem of materials) {
        const pixel = gen.generate(elem.getNamePath(), elem, ctx).getSourceCode('pixel');
        if (!(pixel.length > 0)) return `empty shader for ${elem.getNamePath()}`;
        shaders.push(`${elem.getNamePath()}: ${pixel.length} characters`);
    }
    const defs = doc.getNodes().map((n) => n.getNodeDef().getName()).join(', ');
    console.log(`${file}: valid; ${defs}; ESSL pixel shaders of ${shaders.join(', ')} ` +
                `(MaterialX ${mx.getVersionString()})`);
    return null;
}

async function main() {
    const [moduleDir, ...files] = process.argv.slice(2);
    let mx, gen, ctx, stdlib;
    try {
        mx = await loadMaterialX(moduleDir);
        gen = mx.EsslShaderGenerator.create();
        ctx = new mx.GenContext(gen);
        stdlib = mx.loadStandardLibraries(ctx);
    } catch (e) {
        console.error(`cannot load MaterialX from ${moduleDir}: ${e.message || e}`);
        return 2;
    }
    let failed = 0;
    for (const file of files) {
        let problem;
        try {
            problem = await check(mx, gen, ctx, stdlib, file);
        } catch (e) {
            problem = `MaterialX failed: ${e.message || e}`;
        }
        if (problem) {
            console.log(`${file}: ${problem}`);
            failed = 1;
        }
    }
    return failed;
}

main().then((code) => process.exit(code));
