// Validates glTF files with the Khronos glTF validator (npm package
// `gltf-validator`, found through NODE_PATH): prints each file's counts of
// errors, warnings, infos and hints and every error and warning, and exits
// with status 1 if any file has an error or a warning.
//
// Usage: NODE_PATH=<folder holding node_modules/gltf-validator> node validate_gltf.js FILE...
"use strict";

const fs = require("fs");
const path = require("path");
const validator = require("gltf-validator");

const SEVERITY = ["error", "warning", "info", "hint"];

async function validate(file) {
    const bytes = new Uint8Array(fs.readFileSync(file));
    const report = await validator.validateBytes(bytes, {
        uri: path.basename(file),
        maxIssues: 0, // report every issue
        // Baked files embed their buffers; anything else is read beside the file.
        externalResourceFunction: (uri) =>
            new Promise((resolve, reject) => {
                fs.readFile(path.join(path.dirname(file), decodeURIComponent(uri)), (err, data) =>
                    err ? reject(err.toString()) : resolve(new Uint8Array(data)));
            }),
    });
    const i = report.issues;
    console.log(
        `${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ` +
        `${i.numHints} hints (validator ${report.validatorVersion})`);
    const others = new Map();
    for (const m of i.messages) {
        if (m.severity <= 1) {
            console.log(`  ${SEVERITY[m.severity]} ${m.code} at ${m.pointer || "-"}: ${m.message}`);
        } else {
            others.set(m.code, (others.get(m.code) || 0) + 1);
        }
    }
    for (const [code, n] of others) {
        console.log(`  (${n} x ${code})`);
    }
    return i.numErrors + i.numWarnings;
}

async function main() {
    const files = process.argv.slice(2);
    if (files.length === 0) {
        console.error("usage: node validate_gltf.js FILE...");
        process.exit(2);
    }
    let issues = 0;
    for (const f of files) {
        issues += await validate(f);
    }
    if (issues > 0) {
        console.error(`glTF validation failed: ${issues} errors and warnings`);
        process.exit(1);
    }
}

main().catch((e) => {
    console.error(`glTF validation could not run: ${e}`);
    process.exit(1);
});
