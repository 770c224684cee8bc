// baseline.js: the MaterialX-style retroreflective GGX baseline on the look-dev page, fitted to
// the node's R_A table. MaterialX 1.39.4 cannot generate it (its dielectric_bsdf has no
// `retroreflective` input), so the page renders the GLSL that glsl_gen generates from the
// baseline's one source, nodes/mrm_core.inc (`retroprism view` serves it as site.json's
// "baseline"), in a small vertex/fragment pair that reads the uniforms the renderer sets for
// MaterialX's shaders; the fit is the C++ library's, asked of the view server (web/serve.py,
// POST /fit-baseline: `retroprism fit --ra TABLE --baseline-only --json`).
import { LIGHT_POINT } from './mx.js';

// MaterialX's vertex stage, reduced to what the baseline reads: world position, normal, tangent.
const VERTEX = `#version 300 es
precision highp float;
uniform mat4 u_worldMatrix;
uniform mat4 u_viewProjectionMatrix;
uniform mat4 u_worldInverseTransposeMatrix;
in vec3 i_position;
in vec3 i_normal;
in vec3 i_tangent;
out vec3 positionWorld;
out vec3 normalWorld;
out vec3 tangentWorld;
void main() {
  vec4 hPositionWorld = u_worldMatrix * vec4(i_position, 1.0);
  gl_Position = u_viewProjectionMatrix * hPositionWorld;
  positionWorld = hPositionWorld.xyz;
  normalWorld = normalize((u_worldInverseTransposeMatrix * vec4(i_normal, 0.0)).xyz);
  tangentWorld = normalize((u_worldMatrix * vec4(i_tangent, 0.0)).xyz);
}`;

// MaterialX's light loop for the page's one light (renderer.js): a directional light (its
// direction the light's travel direction) or a point light (LIGHT_POINT) with the inverse-square
// law the page applies to MaterialX's point light (web/mx.js: distance^decay_rate). As in
// MaterialX's surface shader, intensity * f * N.L with the normal facing the viewer
// (mx_forward_facing_normal); opaque: alpha 1.
function fragment(library) {
  return `#version 300 es
precision highp float;
precision highp int;
${library}
struct LightData {
  int type;
  vec3 direction;
  vec3 position;
  vec3 color;
  float intensity;
  float decay_rate;
};
uniform LightData u_lightData[1];
uniform int u_numActiveLightSources;
uniform vec3 u_viewPosition;
uniform float u_mrm_roughness;
uniform float u_mrm_ior;
uniform float u_mrm_specular;
uniform vec3 u_mrm_tint;
uniform vec3 u_mrm_color;
in vec3 positionWorld;
in vec3 normalWorld;
in vec3 tangentWorld;
out vec4 color;
void main() {
  vec3 V = normalize(u_viewPosition - positionWorld);
  vec3 N = normalize(normalWorld);
  if (dot(N, V) < 0.0) N = -N;
  vec3 sum = vec3(0.0);
  if (u_numActiveLightSources > 0) {
    LightData light = u_lightData[0];
    vec3 L;
    vec3 intensity;
    if (light.type == ${LIGHT_POINT}) {
      L = light.position - positionWorld;
      float distance = length(L);
      L /= distance;
      intensity = light.color * light.intensity / pow(distance, light.decay_rate);
    } else {
      L = -light.direction;
      intensity = light.color * light.intensity;
    }
    vec3 specularLobe;
    vec3 diffuseLobe;
    rp_mrm_lobes_in_frame(u_mrm_roughness, u_mrm_ior, u_mrm_specular, u_mrm_tint, u_mrm_color,
                          N, tangentWorld, L, V, specularLobe, diffuseLobe);
    sum = intensity * (specularLobe + diffuseLobe) * max(dot(N, L), 0.0);
  }
  color = vec4(sum, 1.0);
}`;
}

// The baseline's program sources around the generated library (site.json's "baseline").
export function baselineShader(library) {
  return { vertex: VERTEX, fragment: fragment(library) };
}

// The fitted parameters ("mrm" "params" of the server's answer) as the renderer's uniforms.
export function baselineUniforms(params) {
  return [
    { name: 'u_mrm_roughness', type: 'float', value: params.roughness },
    { name: 'u_mrm_ior', type: 'float', value: params.ior },
    { name: 'u_mrm_specular', type: 'float', value: params.specular },
    { name: 'u_mrm_tint', type: 'color3', value: params.tint },
    { name: 'u_mrm_color', type: 'color3', value: params.color },
  ];
}

// The R_A table `y` (rows [observation][entrance], luminance Y) as the CSV the fit reads
// (io/ra_table.h), rotation 0; numbers in JavaScript's shortest round-trip form, so the server
// reads back exactly these doubles. Entries with R_A <= 0 are left out: the fit works on
// ln R_A and the reader refuses them. Returns { csv, entries: [{observation, entrance, ra}],
// skipped }.
export function raTableCsv(observation, entrance, y) {
  const lines = ['observation_deg,entrance_deg,rotation_deg,ra'];
  const entries = [];
  let skipped = 0;
  observation.forEach((a, i) =>
    entrance.forEach((b, j) => {
      const ra = y[i][j];
      if (!(ra > 0)) {
        ++skipped;
        return;
      }
      entries.push({ observation: a, entrance: b, ra });
      lines.push(`${a},${b},0,${ra}`);
    }),
  );
  return { csv: `${lines.join('\n')}\n`, entries, skipped };
}

// Posts the CSV to the view server's fit; its JSON answer, or an Error with the server's
// message (a table it refused, a server that cannot fit).
export async function fitBaseline(csv) {
  let r;
  try {
    r = await fetch('/fit-baseline', { method: 'POST', headers: { 'Content-Type': 'text/csv' }, body: csv });
  } catch (e) {
    throw new Error(`the view server did not answer POST /fit-baseline: ${e.message}`);
  }
  const text = await r.text();
  let answer = null;
  try {
    answer = JSON.parse(text);
  } catch (e) {
    // not JSON: a server other than retroprism view's (e.g. a plain static server)
  }
  if (!r.ok || !answer || answer.error) {
    const reason = answer && answer.error ? answer.error : `HTTP ${r.status} ${r.statusText}`;
    throw new Error(`the server could not fit the baseline: ${reason}` +
      (answer ? '' : ' (serve the page with `retroprism view`, whose server fits it)'));
  }
  return answer;
}
