// mx.js: MaterialX 1.39.4 in the browser (the WebAssembly build the project pins in
// materialx/tools/package-lock.json) over the node library materialx/rp_pbrlib: reads a
// document, finds its retroreflector node and generates the ESSL (WebGL2) shader of its material.
// The same steps as materialx/tools/mx.cjs, which generates the library's shaders in Node.js.
import MaterialX from '../materialx/tools/node_modules/@needle-tools/materialx/bin/JsMaterialXGenShader.js';

const BIN = new URL('../materialx/tools/node_modules/@needle-tools/materialx/bin/', import.meta.url);
const LIBRARY = new URL('../materialx/rp_pbrlib/', import.meta.url);

// The library's files (written by retroprism_glsl_gen, glsl_gen/glsl_gen.cpp).
const LIBRARY_FILES = [
  'rp_pbrlib_defs.mtlx',
  'rp_pbrlib_ng.mtlx',
  'genglsl/rp_pbrlib_genglsl_impl.mtlx',
  'genglsl/rp_prismatic_retroreflector_bsdf.glsl',
];

export const NODE_CATEGORY = 'rp_prismatic_retroreflector_bsdf';
// Light type ids of the generated light loop (u_lightData[i].type).
export const LIGHT_DIRECTIONAL = 1;
export const LIGHT_POINT = 2;

async function fetchText(url) {
  const r = await fetch(url);
  if (!r.ok) throw new Error(`${url}: HTTP ${r.status}`);
  return r.text();
}

// C++ exceptions reach JavaScript as numbers (MATERIALX.md); their text.
export function errorText(mx, e) {
  if (typeof e === 'number') return mx.getExceptionMessage(e);
  return String(e && e.message ? e.message : e);
}

// Copies the files into the module's virtual file system under /dir (MaterialX's source search
// path is "/") and imports their documents into `lib`, with source URIs so that the
// implementations' file= attributes resolve.
async function loadFiles(mx, lib, base, dir, files) {
  for (const rel of files) {
    const text = await fetchText(new URL(rel, base));
    const path = `${dir}/${rel}`;
    const folder = path.slice(0, path.lastIndexOf('/'));
    mx.FS_createPath('/', folder.slice(1), true, true);
    mx.FS_createDataFile(folder, path.slice(folder.length + 1), text, true, true, true);
    if (rel.endsWith('.mtlx')) {
      const doc = mx.createDocument();
      await mx.readFromXmlString(doc, text);
      doc.setSourceUri(path);
      lib.importLibrary(doc);
    }
  }
}

// The loaded module, the standard libraries and rp_pbrlib, and a generation
// context with the lights bound: ESSL, linear output (the page encodes for display itself).
export async function loadMaterialX() {
  const mx = await MaterialX({
    locateFile: (p) => new URL(p.endsWith('.data') ? 'JsMaterialXGenShader.data.txt' : p, BIN).href,
  });
  const gen = mx.EsslShaderGenerator.create();
  const ctx = new mx.GenContext(gen);
  const stdlib = mx.loadStandardLibraries(ctx);
  const lib = mx.createDocument();
  await loadFiles(mx, lib, LIBRARY, '/rp_pbrlib', LIBRARY_FILES);
  const opts = ctx.getOptions();
  opts.hwSrgbEncodeOutput = false;
  // Direct light only, as the C++ night render: no environment lookups.
  opts.hwSpecularEnvironmentMethod = mx.HwSpecularEnvironmentMethod.SPECULAR_ENVIRONMENT_NONE;
  opts.hwMaxActiveLightSources = 2;
  const all = mx.createDocument();
  all.importLibrary(stdlib);
  all.importLibrary(lib);
  mx.HwShaderGenerator.bindLightShader(all.getNodeDef('ND_directional_light'), LIGHT_DIRECTIONAL, ctx);
  mx.HwShaderGenerator.bindLightShader(all.getNodeDef('ND_point_light'), LIGHT_POINT, ctx);
  return { mx, gen, ctx, stdlib, lib };
}

// The node input feeding `input` (a connection by nodename), or null.
function upstream(graph, input) {
  if (!input) return null;
  const name = input.getNodeName();
  return name ? graph.getNode(name) : null;
}

// The node's enums are integer enums (enumvalues 0, 1, ...); a document written before gives
// them as their names with type="string", as the C++ reader (io/mtlx_reader.cpp) also accepts:
// such inputs become the integer their name stands for (an unknown name is left for
// validation to report).
function upgradeEnums(doc, bsdf) {
  const nodedef = doc.getNodeDef('ND_' + NODE_CATEGORY);
  for (const input of bsdf.getInputs()) {
    const def = nodedef.getInput(input.getName());
    if (!def || def.getType() !== 'integer' || input.getType() !== 'string') continue;
    const k = def.getAttribute('enum').split(',').indexOf(input.getValueString());
    if (k >= 0) input.setValueString(def.getAttribute('enumvalues').split(',')[k], 'integer');
  }
}

// Reads `xml` (named `label` in messages) and finds the material to show: `materialName` or the
// first whose surface shader's bsdf is the retroprism node. Throws an Error whose text names
// the document and what is wrong.
export async function readDocument(m, xml, label, materialName = '') {
  const { mx, stdlib, lib } = m;
  const doc = mx.createDocument();
  try {
    await mx.readFromXmlString(doc, xml);
  } catch (e) {
    throw new Error(`${label}: not a MaterialX document: ${errorText(mx, e)}`);
  }
  doc.importLibrary(stdlib);
  doc.importLibrary(lib);
  const materials = doc.getMaterialNodes();
  if (materials.length === 0) throw new Error(`${label}: no <surfacematerial> in the document`);
  const problems = [];
  for (const material of materials) {
    if (materialName && material.getName() !== materialName) continue;
    const surface = upstream(doc, material.getInput('surfaceshader'));
    const bsdf = surface ? upstream(doc, surface.getInput('bsdf')) : null;
    if (!bsdf || bsdf.getCategory() !== NODE_CATEGORY) {
      problems.push(`material "${material.getName()}": its surface shader's bsdf is not a <${NODE_CATEGORY}> node`);
      continue;
    }
    upgradeEnums(doc, bsdf);
    if (!doc.validate())
      throw new Error(`${label}: the document does not validate against the MaterialX libraries and rp_pbrlib`);
    return { xml, doc, material, surface, bsdf };
  }
  if (materialName && problems.length === 0)
    throw new Error(`${label}: no material named "${materialName}"`);
  throw new Error(`${label}: ${problems.join('; ')}`);
}

// MaterialX 1.39's point light attenuates by (d + 1)^decay_rate (finite at d = 0); the
// headlight of the C++ scene and of R_A photometry is an isotropic point source with the
// inverse-square law, 1/d^2, which at the scene's 8 m differs from the former by up to 1%
// across the sphere. The page's shader uses d^decay_rate (decay_rate 2).
const POINT_LIGHT_ATTENUATION = 'float attenuation = pow(distance + 1.0, light.decay_rate + M_FLOAT_EPS);';
const INVERSE_POWER_ATTENUATION = 'float attenuation = pow(distance, light.decay_rate);';

// The ESSL of the material: { vertex, fragment } source and the uniforms' values, with the
// edits the generated code needs here: highp floats (the generator writes mediump, 10-bit
// mantissas: far from the C++ reference's doubles), the declaration of u_refractionTwoSided,
// which 1.39.4 uses without declaring when no environment is bound (MATERIALX.md), and the
// point light's inverse-square law (above).
export function generateEssl(m, found) {
  const { mx, gen, ctx } = m;
  let shader;
  try {
    shader = gen.generate(found.material.getName(), found.material, ctx);
  } catch (e) {
    throw new Error(`material "${found.material.getName()}": shader generation failed: ${errorText(mx, e)}`);
  }
  const fix = (s) =>
    s
      .replace(/precision mediump float;/, 'precision highp float;\nprecision highp int;')
      .replace(/^#version 300 es\n/, (v) =>
        /uniform bool u_refractionTwoSided;/.test(s) ? v : v + '#define u_refractionTwoSided false\n');
  const fragment = shader.getSourceCode('pixel');
  if (!fragment.includes(POINT_LIGHT_ATTENUATION))
    throw new Error(`MaterialX's point light no longer reads "${POINT_LIGHT_ATTENUATION}": update web/mx.js`);
  return {
    vertex: fix(shader.getSourceCode('vertex')),
    fragment: fix(fragment.replace(POINT_LIGHT_ATTENUATION, INVERSE_POWER_ATTENUATION)),
    uniforms: uniformDefaults(shader),
  };
}

// The public uniforms of the pixel stage with the values MaterialX gives them (the document's
// inputs, the nodedefs' defaults): [{name, type, value}], numbers and number arrays.
function uniformDefaults(shader) {
  const block = shader.getStage('pixel').getUniformBlocks()['PublicUniforms'];
  const list = [];
  for (let i = 0; i < block.size(); ++i) {
    const port = block.get(i);
    const v = port.getValue();
    if (!v) continue;
    const type = port.getType().getName();
    const text = v.getValueString();
    let value;
    if (type === 'float' || type === 'integer') value = Number(text);
    else if (type === 'boolean') value = text === 'true' ? 1 : 0;
    else if (/^(color|vector)[234]$/.test(type)) value = text.split(',').map(Number);
    else continue;
    list.push({ name: port.getVariable(), type, value });
  }
  return list;
}

// The node's inputs set in the document: name -> value string (MaterialX's text form).
export function documentInputs(found) {
  const values = {};
  for (const input of found.bsdf.getInputs()) {
    if (input.getNodeName() || input.getInterfaceName() || input.getOutputString()) continue;
    values[input.getName()] = input.getValueString();
  }
  return values;
}

// The document as text with the node's inputs replaced by `values` (name -> value string, of
// MaterialX type types[name]): the tuned material, in the document it came from (read again,
// without the libraries imported for generation).
export async function exportDocument(m, found, values, types) {
  const { mx } = m;
  const doc = mx.createDocument();
  await mx.readFromXmlString(doc, found.xml);
  const bsdf = doc.getNode(found.bsdf.getName());
  for (const [name, value] of Object.entries(values)) {
    const input = bsdf.getInput(name) || bsdf.addInput(name, types[name]);
    input.setValueString(value, types[name]);
  }
  return mx.writeToXmlString(doc);
}
