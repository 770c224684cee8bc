// mx.cjs: real MaterialX 1.39.4 (the WebAssembly build in @needle-tools/materialx, pinned by
// package-lock.json) over the node library in materialx/rp_pbrlib. Test-time tool.
//
//   node mx.cjs validate DOC.mtlx...            validate documents (with stdlib + rp_pbrlib)
//   node mx.cjs implementations                 every rp nodedef has a genglsl implementation
//                                               and a nodegraph, and what each target chooses
//   node mx.cjs generate [--portable] [--targets T,...] DOC.mtlx... OUTDIR
//       the shaders of every material for the targets T (default: all of glsl, essl, vulkan,
//       msl, osl, mdl) as MATERIAL.T.vert and .frag (OSL and MDL: MATERIAL.osl, MATERIAL.mdl);
//       --portable loads the library without its genglsl implementation, so that the GLSL
//       targets too use the portable nodegraph (how its GLSL is measured on OpenGL);
//       --osl-closure also loads the opt-in library materialx/rp_pbrlib_closure, whose genosl
//       implementation calls the renderer's retroprism_bsdf closure instead of the nodegraph.
//       For glsl, MATERIAL.glsl.json beside the shaders: the pixel stage's public uniforms
//       (variable, type, the element path, the value; for filename inputs the value with the
//       document's fileprefix applied, for colour inputs their active colour space) and the
//       categories of the nodes the material reaches, so that a renderer can bind textures
//       and tell which nodes a shader holds.
//       Before generating, each document is checked: every node must have a nodedef (an
//       unknown node or a node whose inputs match no signature), the document must pass
//       MaterialX's validate(); the message names the element and the file.
//   node mx.cjs osl-includes OUTDIR             writes MaterialX's genosl include folder
//       (libraries/stdlib/genosl/include: mx_funcs.h, vector2.h, ...), which the generated OSL
//       includes, as OUTDIR/*.h: oslc's include path for compiling it.
//
// Exit status 0 when everything succeeded; messages name the document and what failed.
'use strict';
const fs = require('fs');
const os = require('os');
const path = require('path');

const BIN = path.join(__dirname, 'node_modules', '@needle-tools', 'materialx', 'bin');
const LIBRARY = path.resolve(__dirname, '..', 'rp_pbrlib');
const CLOSURE_LIBRARY = path.resolve(__dirname, '..', 'rp_pbrlib_closure');

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
async function loadLibrary(mx, portable, oslClosure) {
  const lib = mx.createDocument();
  await loadFolder(mx, lib, LIBRARY, (rel) => !(portable && rel.split(path.sep)[0] === 'genglsl'));
  if (oslClosure) await loadFolder(mx, lib, CLOSURE_LIBRARY, () => true);
  return lib;
}

// The files of one library folder (those `keep` accepts) into the virtual file system under
// its name, its documents imported into `lib`.
async function loadFolder(mx, lib, folder, keep) {
  for (const rel of listFiles(folder)) {
    if (!keep(rel)) continue;
    const dir = path.posix.join(path.basename(folder), path.dirname(rel).split(path.sep).join('/'));
    mx.FS_createPath('/', dir, true, true);
    const data = fs.readFileSync(path.join(folder, rel));
    mx.FS_createDataFile('/' + dir, path.basename(rel), data, true, true, true);
    if (rel.endsWith('.mtlx')) {
      const doc = mx.createDocument();
      await mx.readFromXmlString(doc, data.toString('utf8'));
      doc.setSourceUri('/' + path.posix.join(dir, path.basename(rel)));
      lib.importLibrary(doc);
    }
  }
}

// MaterialX's genosl include files, from the package's data file (the files of the standard
// libraries, at the offsets its loader script lists); the number written.
function writeOslIncludes(outDir) {
  const loader = fs.readFileSync(path.join(BIN, 'JsMaterialXGenShader.js'), 'utf8');
  const data = fs.readFileSync(path.join(BIN, 'JsMaterialXGenShader.data.txt'));
  const prefix = '/libraries/stdlib/genosl/include/';
  const entry = /filename:"([^"]+)",start:(\d+),end:(\d+)/g;
  fs.mkdirSync(outDir, { recursive: true });
  let written = 0;
  for (let m; (m = entry.exec(loader));) {
    if (!m[1].startsWith(prefix)) continue;
    fs.writeFileSync(path.join(outDir, m[1].substring(prefix.length)), data.subarray(+m[2], +m[3]));
    written++;
  }
  return written;
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

// Each target's name, generator and whether it renders (lights bound, vertex and pixel stages).
function targetTable(mx) {
  return {
    glsl: [mx.GlslShaderGenerator, true],
    essl: [mx.EsslShaderGenerator, true],
    vulkan: [mx.VkShaderGenerator, true],
    msl: [mx.MslShaderGenerator, true],
    osl: [mx.OslShaderGenerator, false],
    mdl: [mx.MdlShaderGenerator, false],
  };
}

// Writes the shaders of one material: a hardware target's two stages, or OSL's or MDL's one.
function writeShader(shader, base, hw) {
  if (hw) {
    fs.writeFileSync(`${base}.vert`, shader.getSourceCode('vertex'));
    fs.writeFileSync(`${base}.frag`, shader.getSourceCode('pixel'));
    return `${base}.{vert,frag}`;
  }
  fs.writeFileSync(base, shader.getSourceCode('pixel'));
  return base;
}

// An element as MaterialX prints it in its messages: <category name="...">.
function describe(e) {
  return `<${e.getCategory()} name="${e.getName()}">`;
}

// What is wrong with a document before any shader is generated: nodes without a nodedef (at the
// top level and in node graphs), then MaterialX's own validation message (type mismatches,
// dangling connections). Cycles are reported by the generator ("Encountered cycle at element").
function documentProblems(doc) {
  const problems = [];
  const graphs = [doc].concat(doc.getNodeGraphs().filter((g) => !g.hasNodeDefString()));
  for (const g of graphs) {
    for (const n of g.getNodes()) {
      if (n.getNodeDef()) continue;
      const where = g === doc ? '' : ` in ${describe(g)}`;
      const known = doc.getMatchingNodeDefs(n.getCategory()).length > 0;
      problems.push(known
        ? `${describe(n)}${where}: no nodedef of '${n.getCategory()}' matches its type '${n.getType()}' and inputs`
        : `${describe(n)}${where}: unknown node category '${n.getCategory()}' (no nodedef in the standard library or rp_pbrlib)`);
    }
  }
  const result = {};
  if (!doc.validate(result)) {
    const text = String(result.message || 'invalid').trim();
    for (const line of text.split('\n')) if (line.length > 0 && !problems.some((p) => p.includes(line))) problems.push(line);
  }
  return problems;
}

// The pixel stage's public uniforms of a generated shader and the node categories the material
// reaches, as JSON (see the header).
function writeManifest(doc, material, shader, file) {
  const uniforms = [];
  const block = shader.getStage('pixel').getUniformBlocks().PublicUniforms;
  for (let i = 0; i < block.size(); i++) {
    const port = block.get(i);
    const entry = { variable: port.getVariable(), type: port.getType().getName(), path: port.getPath() };
    const value = port.getValue();
    entry.value = value ? value.getValueString() : '';
    // Inputs the document leaves at their defaults have a path but no element: their node is
    // the path's parent.
    const slash = entry.path.lastIndexOf('/');
    const node = slash > 0 ? doc.getDescendant(entry.path.substring(0, slash)) : null;
    if (node) {
      const element = doc.getDescendant(entry.path);
      if (element && entry.type === 'filename') entry.value = element.getResolvedValueString();
      entry.colorspace = (element || node).getActiveColorSpace();
      entry.node = node.getName();
      entry.category = node.getCategory();
      entry.nodetype = node.getType();
    }
    uniforms.push(entry);
  }
  const categories = new Set();
  const seen = new Set();
  const visit = (node) => {
    if (!node || seen.has(node.getNamePath())) return;
    seen.add(node.getNamePath());
    categories.add(node.getCategory());
    for (const input of node.getInputs()) {
      const up = input.getConnectedNode();
      if (up) visit(up);
      if (input.hasNodeGraphString()) {
        const g = doc.getNodeGraph(input.getNodeGraphString());
        if (g) for (const n of g.getNodes()) visit(n);
      }
    }
  };
  visit(material);
  const manifest = { material: material.getName(), uniforms, categories: [...categories].sort() };
  fs.writeFileSync(file, JSON.stringify(manifest, null, 1) + '\n');
}

// Writes the shaders of every material of one document for one target; the failures. A
// document is checked (documentProblems, whose validation of the document with the imported
// libraries takes most of a generation's time) for the first target only: `checked` keeps the
// verdict by file, and a document that failed is not generated for the other targets.
async function generateDocument(mx, file, name, hw, gen, ctx, stdlib, lib, outDir, checked) {
  if (checked.get(file) === false) return 0; // its errors are printed and counted once
  let doc;
  try {
    doc = await readDocument(mx, file, stdlib, lib);
  } catch (e) {
    console.log(`${file}: error: ${message(mx, e)}`);
    checked.set(file, false);
    return 1;
  }
  if (!checked.has(file)) {
    const problems = documentProblems(doc);
    checked.set(file, problems.length === 0);
    if (problems.length > 0) {
      for (const p of problems) console.log(`${file}: error: ${p}`);
      return 1;
    }
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
      const written = writeShader(shader, path.join(outDir, `${m.getName()}.${name}`), hw);
      if (name === 'glsl') writeManifest(doc, m, shader, path.join(outDir, `${m.getName()}.glsl.json`));
      console.log(`${file}: ${m.getName()} ${name}: generated ${written}`);
    } catch (e) {
      console.log(`${file}: ${m.getName()} ${name}: error: ${message(mx, e)}`);
      failures++;
    }
  }
  return failures;
}

// The implementation MaterialX chooses for each target (NodeDef::getImplementation, which follows
// the targetdefs' inheritance: genmsl and essl inherit genglsl). Every nodedef must have the
// genglsl implementation for the GLSL family and its nodegraph for OSL and MDL; the failures.
function implementationChoices(mx, doc, defs) {
  const expected = { genglsl: 'IM_', essl: 'IM_', genmsl: 'IM_', genosl: 'NG_', genmdl: 'NG_' };
  let failures = 0;
  for (const nd of defs) {
    for (const [target, prefix] of Object.entries(expected)) {
      const impl = doc.getNodeDef(nd.getName()).getImplementation(target);
      const name = impl ? impl.getName() : '(none)';
      const kind = impl ? impl.getCategory() : '';
      const ok = name.startsWith(prefix);
      console.log(`${nd.getName()}: target ${target}: ${name} ${kind}${ok ? '' : ' UNEXPECTED'}`);
      if (!ok) failures++;
    }
  }
  return failures;
}

async function main() {
  const argv = process.argv.slice(2);
  const command = argv[0];
  let args = argv.slice(1);
  const portable = args.includes('--portable');
  const oslClosure = args.includes('--osl-closure');
  args = args.filter((a) => a !== '--portable' && a !== '--osl-closure');
  let targetNames = ['glsl', 'essl', 'vulkan', 'msl', 'osl', 'mdl'];
  const t = args.indexOf('--targets');
  if (t >= 0) {
    targetNames = (args[t + 1] || '').split(',');
    args.splice(t, 2);
  }
  if (command === 'osl-includes') {
    const written = args.length === 1 ? writeOslIncludes(args[0]) : 0;
    console.log(`osl-includes: wrote ${written} files`);
    process.exit(written > 0 ? 0 : 1);
  }
  const mx = await loadMaterialX();
  const lib = await loadLibrary(mx, portable, oslClosure);
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
    failures += implementationChoices(mx, doc, defs);
  } else if (command === 'generate') {
    const files = args.slice(0, -1);
    const outDir = args[args.length - 1];
    if (files.length === 0) {
      console.log('usage: node mx.cjs generate DOC.mtlx... OUTDIR');
      process.exit(2);
    }
    fs.mkdirSync(outDir, { recursive: true });
    const table = targetTable(mx);
    for (const name of targetNames) {
      if (!table[name]) {
        console.log(`--targets: unknown target '${name}' (targets: ${Object.keys(table).join(', ')})`);
        process.exit(2);
      }
    }
    const checked = new Map();
    for (const name of targetNames) {
      const [generator, hw] = table[name];
      const { gen, ctx, stdlib } = await context(mx, generator, hw);
      for (const file of files) failures += await generateDocument(mx, file, name, hw, gen, ctx, stdlib, lib, outDir, checked);
    }
  } else {
    console.log('usage: node mx.cjs validate DOC... | implementations | generate [--portable] [--osl-closure] [--targets T,...] DOC... OUTDIR | osl-includes OUTDIR');
    process.exit(2);
  }
  process.exit(failures === 0 ? 0 : 1);
}

main().catch((e) => {
  console.log(`mx.cjs: ${e && e.stack ? e.stack : e}`);
  process.exit(1);
});
