// node validate_gltf.js FILE.glb|FILE.gltf: the Khronos glTF-Validator's report as JSON on stdout.
// The gltf-validator package is found through NODE_PATH (tests/gltf_tools.py sets it).
const fs = require("fs");
const path = require("path");
const validator = require("gltf-validator");

const file = path.resolve(process.argv[2]);
validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
    uri: path.basename(file),
    maxIssues: 100,
    externalResourceFunction: (uri) => new Promise((resolve, reject) => {
        fs.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)),
                    (err, data) => (err ? reject(err.toString()) : resolve(new Uint8Array(data))));
    }),
}).then((report) => {
    process.stdout.write(JSON.stringify(report));
}).catch((error) => {
    process.stderr.write(String(error) + "\n");
    process.exit(1);
});
