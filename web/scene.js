// scene.js: the night scene of `retroprism render` (analysis/night_render.h, which defines it):
// camera at the origin looking down -z (+y up, pinhole), a diamond sign and a sphere at 8 m, a
// headlight below the eye placed for an observation angle at the sign's centre, the sign turned
// about the vertical for an entrance angle there. The browser test compares the page's frame
// with the C++ render pixel by pixel, so any drift between the two is caught.
const DEG = Math.PI / 180;

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const length = (a) => Math.sqrt(dot(a, a));
const normalize = (a) => scale(a, 1 / length(a));
const angleDeg = (a, b) => Math.atan2(length(cross(a, b)), dot(a, b)) / DEG;

const UP = [0, 1, 0];
const SIGN_CENTRE = [-0.62, 0, -8];
const SIGN_SIDE = 0.85; // metres, a square turned 45 degrees in its plane
const SPHERE_CENTRE = [0.75, 0, -8.2];
const SPHERE_RADIUS = 0.5;
const EYE = [0, 0, 0];

// The scene for an image of width x height: camera half-extents, the headlight, the sign's
// frame, and the angles measured at the sign's centre (night_render.cpp, build_scene).
export function buildScene(width, height, observationDeg, entranceDeg) {
  const aspect = width / height;
  const tanX = Math.max(1.35, 0.8 * aspect) / 8;
  const tanY = tanX / aspect;
  // The headlight below the eye: first placed for a sign facing the eye, then refined.
  const D = length(sub(SIGN_CENTRE, EYE));
  let h = D * Math.tan(observationDeg * DEG);
  let light = sub(EYE, [0, h, 0]);
  for (let it = 0; it < 3 && observationDeg > 0; ++it) {
    const a = angleDeg(sub(light, SIGN_CENTRE), sub(EYE, SIGN_CENTRE));
    h *= observationDeg / a;
    light = sub(EYE, [0, h, 0]);
  }
  const toLight = normalize(sub(light, SIGN_CENTRE));
  const yaw = Math.atan2(toLight[0], toLight[2]) - entranceDeg * DEG;
  const n = [Math.sin(yaw), 0, Math.cos(yaw)];
  const u = normalize(cross(UP, n));
  const v = cross(n, u);
  const d = sub(light, SIGN_CENTRE);
  return {
    tanX,
    tanY,
    eye: EYE,
    // Intensity such that the illuminance perpendicular to the light at the sign's centre is 1.
    light: { position: light, intensity: dot(d, d) },
    sign: { centre: SIGN_CENTRE, normal: n, tangent: u, bitangent: v, halfDiagonal: SIGN_SIDE / Math.SQRT2 },
    sphere: { centre: SPHERE_CENTRE, radius: SPHERE_RADIUS },
    observationAtSign: angleDeg(d, sub(EYE, SIGN_CENTRE)),
    entranceAtSign: angleDeg(d, n),
  };
}

// Interleaved vertices (position, normal, tangent: 9 floats) and triangle indices.
function mesh(vertices, indices) {
  return { vertices: new Float32Array(vertices), indices: new Uint32Array(indices) };
}

// The diamond: corners at the centre +- halfDiagonal along the sign's horizontal and vertical axes.
export function signMesh(sign) {
  const { centre: c, normal: n, tangent: t, bitangent: b, halfDiagonal: r } = sign;
  const corners = [add(c, scale(t, r)), add(c, scale(b, r)), add(c, scale(t, -r)), add(c, scale(b, -r))];
  const v = [];
  for (const p of corners) v.push(...p, ...n, ...t);
  return mesh(v, [0, 1, 2, 0, 2, 3]);
}

// A latitude-longitude sphere; normals exact at the vertices, tangents along the parallels
// (normalize(up x n), +x at the poles), as the C++ scene's.
export function sphereMesh(sphere, rings = 512, segments = 1024) {
  const v = [];
  const idx = [];
  for (let i = 0; i <= rings; ++i) {
    const theta = (i / rings) * Math.PI;
    for (let j = 0; j <= segments; ++j) {
      const phi = (j / segments) * 2 * Math.PI;
      const n = [Math.sin(theta) * Math.sin(phi), Math.cos(theta), Math.sin(theta) * Math.cos(phi)];
      const tg = cross(UP, n);
      const t = length(tg) > 1e-9 ? normalize(tg) : [1, 0, 0];
      v.push(...add(sphere.centre, scale(n, sphere.radius)), ...n, ...t);
    }
  }
  for (let i = 0; i < rings; ++i) {
    for (let j = 0; j < segments; ++j) {
      const a = i * (segments + 1) + j;
      const b = a + segments + 1;
      idx.push(a, b, a + 1, a + 1, b, b + 1);
    }
  }
  return mesh(v, idx);
}

// Column-major perspective projection of the camera: a pixel centre's ray is the C++ scene's
// (x_ndc = x / (-z tanX), y_ndc = y / (-z tanY)).
export function projection(scene, near = 0.5, far = 100) {
  const m = new Float32Array(16);
  m[0] = 1 / scene.tanX;
  m[5] = 1 / scene.tanY;
  m[10] = (far + near) / (near - far);
  m[11] = -1;
  m[14] = (2 * far * near) / (near - far);
  return m;
}

export const vec = { sub, add, scale, dot, cross, length, normalize };
