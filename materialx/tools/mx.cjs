// mx.cjs: real MaterialX 1.39.4 (the WebAssembly build in @needle-tools/materialx, pinned by
// package-lock.json) over the node library in materialx/rp_pbrlib. Test-time tool.
//
//   node mx.cjs validate DOC.mtlx...            validate documents (with stdlib + rp_pbrlib)
//   node mx.cjs implementations                 every rp nodedef has a genglsl implementation
//   node mx.cjs generate DOC.mtlx... OUTDIR     GLSL, ESSL and Vulkan shaders of every material
//
// Exit status 0 when everything succeeded; messages name the document and what failed.
'use strict';
const fs = require('fs');
const os = require('os');
const path = require('path');

const BIN = path.join(__dirname, 'node_modules', '@needle-tools', 'materialx', 'bin');
const LIBRARY = path.resolve(__dirname, '..', 'rp_pbrlib');

async function loadMaterialX() {
  // The module ends with an ES `export default`; a CommonJS copy of it loads with require.
  const source = fs.readFileSync(path.join(BIN, 'JsMaterialXGenShader.js'), 'utf8');
  const cjs = path.join(os.tmpdir(), `retroprism_JsMaterialXGenShader_${process.pid}.cjs`);
  fs.writeFileSync(cjs, source.replace(/export default MaterialX;\s*$/, ''));
  try {
    const factory = require(cjs);
    return await factory({
      locateFile: (p) => (p.endsWith('.data') ? path.join(BIN, 'JsMaterialXGenShader.data.txt') : path.join(BIN, p)),
    });
  } finally {
    fs.unlinkSync(cjs);
  }
}

function message(mx, e) {
  return typeof e === 'number' ? mx.getExceptionMessage(e) : String(e && e.message ? e.message : e);
}

function listFiles(dir, rel = '') {
  let out = [];
  for (const entry of fs.readdirSync(path.join(dir, rel), { withFileTypes: true })) {
    const r = path.join(rel, entry.name);
    if (entry.isDirectory()) out = out.concat(listFiles(dir, r));
    else out.push(r);
  }
  return out;
}

// Copies rp_pbrlib into the module's virtual file system (source search path "/") and reads
// its documents, with source URIs so that implementation files resolve.
async function loadLibrary(mx) {
  const lib = mx.createDocument();
  for (const rel of listFiles(LIBRARY)) {
    const dir = path.posix.join('rp_pbrlib', path.dirname(rel).split(path.sep).join('/'));
    mx.FS_createPath('/', dir, true, true);
    const data = fs.readFileSync(path.join(LIBRARY, rel));
    mx.FS_createDataFile('/' + dir, path.basename(rel), data, true, true, true);
    if (rel.endsWith('.mtlx')) {
      const doc = mx.createDocument();
      await mx.readFromXmlString(doc, data.toString('utf8'));
      doc.setSourceUri('/' + path.posix.join(dir, path.basename(rel)));
      lib.importLibrary(doc);
    }
  }
  return lib;
}

async function context(mx, generator, lights) {
  const gen = generator.create();
  const ctx = new mx.GenContext(gen);
  const stdlib = mx.loadStandardLibraries(ctx);
  const opts = ctx.getOptions();
  opts.hwSrgbEncodeOutput = false;
  if (lights) {
    opts.hwMaxActiveLightSources = 2;
    mx.HwShaderGenerator.bindLightShader(stdlib.getNodeDef('ND_directional_light'), 1, ctx);
    mx.HwShaderGenerator.bindLightShader(stdlib.getNodeDef('ND_point_light'), 2, ctx);
  }
  return { gen, ctx, stdlib };
}

async function readDocument(mx, file, stdlib, lib) {
  const doc = mx.createDocument();
  await mx.readFromXmlString(doc, fs.readFileSync(file, 'utf8'));
  doc.setSourceUri(path.resolve(file));
  doc.importLibrary(stdlib);
  doc.importLibrary(lib);
  return doc;
}

// Writes the shaders of every material of one document for one target; the failures.
async function generateDocument(mx, file, name, gen, ctx, stdlib, lib, outDir) {
  let doc;
  try {
    doc = await readDocument(mx, file, stdlib, lib);
  } catch (e) {
    console.log(`${file}: error: ${message(mx, e)}`);
    return 1;
  }
  const materials = doc.getMaterialNodes();
  if (materials.length === 0) {
    console.log(`${file}: no surfacematerial`);
    return 1;
  }
  let failures = 0;
  for (const m of materials) {
    try {
      const shader = gen.generate(m.getName(), m, ctx);
      const base = path.join(outDir, `${m.getName()}.${name}`);
      fs.writeFileSync(`${base}.vert`, shader.getSourceCode('vertex'));
      fs.writeFileSync(`${base}.frag`, shader.getSourceCode('pixel'));
      console.log(`${file}: ${m.getName()} ${name}: generated ${base}.{vert,frag}`);
    } catch (e) {
      console.log(`${file}: ${m.getName()} ${name}: error: ${message(mx, e)}`);
      failures++;
    }
  }
  return failures;
}

async function main() {
  const [command, ...args] = process.argv.slice(2);
  const mx = await loadMaterialX();
  const lib = await loadLibrary(mx);
  let failures = 0;
  if (command === 'validate') {
    const { stdlib } = await context(mx, mx.GlslShaderGenerator, false);
    for (const file of args) {
      try {
        const doc = await readDocument(mx, file, stdlib, lib);
        const ok = doc.validate();
        console.log(`${file}: ${ok ? 'valid' : 'INVALID'}`);
        if (!ok) failures++;
      } catch (e) {
        console.log(`${file}: error: ${message(mx, e)}`);
        failures++;
      }
    }
  } else if (command === 'implementations') {
    const { stdlib } = await context(mx, mx.GlslShaderGenerator, false);
    const doc = mx.createDocument();
    doc.importLibrary(stdlib);
    doc.importLibrary(lib);
    const defs = lib.getNodeDefs();
    const impls = lib.getImplementations();
    for (const nd of defs) {
      const impl = impls.find((i) => i.getNodeDefString() === nd.getName() && i.getTarget() === 'genglsl');
      const file = impl ? impl.getFile() : '';
      const ok = !!impl && file.length > 0 && fs.existsSync(path.join(LIBRARY, 'genglsl', file));
      console.log(`${nd.getName()}: ${ok ? impl.getName() + ' (' + file + ')' : 'NO genglsl implementation'}`);
      if (!ok) failures++;
    }
    if (defs.length === 0) {
      console.log('rp_pbrlib: no nodedefs');
      failures++;
    }
  } else if (command === 'generate') {
    const files = args.slice(0, -1);
    const outDir = args[args.length - 1];
    if (files.length === 0) {
      console.log('usage: node mx.cjs generate DOC.mtlx... OUTDIR');
      process.exit(2);
    }
    fs.mkdirSync(outDir, { recursive: true });
    const targets = [
      ['glsl', mx.GlslShaderGenerator, true],
      ['essl', mx.EsslShaderGenerator, true],
      ['vulkan', mx.VkShaderGenerator, true],
    ];
    for (const [name, generator, lights] of targets) {
      const { gen, ctx, stdlib } = await context(mx, generator, lights);
      for (const file of files) failures += await generateDocument(mx, file, name, gen, ctx, stdlib, lib, outDir);
    }
  } else {
    console.log('usage: node mx.cjs validate DOC... | implementations | generate DOC... OUTDIR');
    process.exit(2);
  }
  process.exit(failures === 0 ? 0 : 1);
}

main().catch((e) => {
  console.log(`mx.cjs: ${e && e.stack ? e.stack : e}`);
  process.exit(1);
});
