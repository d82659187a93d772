// Validate glTF files with the Khronos glTF Validator (npm gltf-validator).
//
//   node validate_gltf.js MODULE_DIR FILE...
//
// MODULE_DIR is the node_modules folder that holds gltf-validator. For every
// file, prints the validator's counts and every message at warning level or
// above; exits 0 when no file has an error, 1 when one has, 2 when the
// validator cannot run (no such module, unreadable file, unknown format).
'use strict';
const fs = require('fs');
const path = require('path');

const SEVERITY = ['error', 'warning', 'info', 'hint'];

async function validate(validator, file) {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
        uri: path.basename(file),
        maxIssues: 100,
        externalResourceFunction: (uri) => Promise.reject(new Error('external resource ' + uri)),
    });
    const issues = report.issues;
    console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
                `${issues.numInfos} infos, ${issues.numHints} hints (validator ` +
                `${report.validatorVersion})`);
    for (const m of issues.messages)
        if (m.severity <= 1)
            console.log(`  ${SEVERITY[m.severity]} ${m.code} at ${m.pointer || '/'}: ${m.message}`);
    return issues.numErrors;
}

async function main() {
    const [moduleDir, ...files] = process.argv.slice(2);
    let validator;
    try {
        validator = require(path.resolve(moduleDir, 'gltf-validator'));
    } catch (e) {
        console.error(`cannot load gltf-validator from ${moduleDir}: ${e.message}`);
        return 2;
    }
    let failed = 0;
    for (const file of files) {
        try {
            if (await validate(validator, file) > 0) failed = 1;
        } catch (e) {
            console.error(`${file}: the validator could not run: ${e}`);
            return 2;
        }
    }
    return failed;
}

main().then((code) => process.exit(code));
