// cube_corner.cpp: canted cube corners in the simulator (see cube_corner.h).
#include "cube_corner.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

namespace retroprism {
namespace sim {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kArcmin = kPi / (180.0 * 60.0);

// The sheet's frame in the cube's at cant `cantDeg` and orientation `psi`: the normal
// n = normalize(a cos(cant) + u sin(cant)), x toward e_1's projection, y = n x x, and the
// rotation by psi (c, s) that carries them to the sheet's axes.
struct SheetFrame {
    dvec3 x, y, n;
    double c, s;
};

SheetFrame sheet_frame(double cantDeg, double psi) {
    const double cant = cantDeg * (kPi / 180.0);
    const dvec3 a = glm::normalize(dvec3(1.0, 1.0, 1.0));
    const dvec3 u = glm::normalize(dvec3(2.0, -1.0, -1.0));
    SheetFrame f;
    f.n = glm::normalize(a * std::cos(cant) + u * std::sin(cant));
    f.x = glm::normalize(dvec3(1.0, 0.0, 0.0) - f.n.x * f.n);
    f.y = glm::cross(f.n, f.x);
    f.c = std::cos(psi);
    f.s = std::sin(psi);
    return f;
}

// The inward face normals (cube's frame) of the corner whose dihedral angles are 90 degrees plus
// dihedralArcmin[k] between the two faces other than k: G_ij = e_i.e_j = sin(that error), e =
// G^(1/2) applied to the axes (the symmetric square root).
void gram_normals(const double dihedralArcmin[3], dvec3 normal[3]) {
    glm::dmat3 g(1.0);
    for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        g[i][j] = g[j][i] = std::sin(dihedralArcmin[k] * kArcmin);
    }
    // Its principal square root by Newton's iteration from the identity, X <- (X + X^-1 G) / 2:
    // quadratic convergence, G being within a few 1e-2 of the identity.
    glm::dmat3 root(1.0);
    for (int it = 0; it < 50; ++it) {
        const glm::dmat3 next = 0.5 * (root + glm::inverse(root) * g);
        double change = 0;
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r)
                change = std::max(change, std::abs(next[c][r] - root[c][r]));
        root = next;
        if (change < 1e-16) break;
    }
    for (int k = 0; k < 3; ++k)
        normal[k] = glm::normalize(dvec3(root[0][k], root[1][k], root[2][k]));
}

// A face hit at the cosine cosK: kPrismRetro when the ray is reflected (always by ideal faces; by
// internal Fresnel reflection for tir prisms, else transmitted; with the metal's reflectance for
// metallized ones, else absorbed), else the outcome that ends it.
PrismOutcome face_loss(const Sheet& sheet, double cosK, Rng& rng) {
    const bool tir = sheet.prism_reflection == f64::RP_PRISM_TIR;
    const double reflectance =
        tir ? f64::rp_fresnel_internal(cosK, sheet.eta)
            : (sheet.prism_reflection == f64::RP_PRISM_METALLIZED ? sheet.metal_reflectance : 1.0);
    if (reflectance < 1.0 && rng.uniform() >= reflectance)
        return tir ? kPrismTransmitted : kPrismAbsorbed;
    return kPrismRetro;
}

// The corner of the face normals `normal` (in the cube's frame; `perfect`: the unit axes, when
// the edges are the normals themselves) at cant `cantDeg` and orientation `psi`.
CubeCorner corner_of_normals(double cantDeg, const dvec3 normal[3], bool perfect, double psi) {
    const SheetFrame f = sheet_frame(cantDeg, psi);
    const dvec3 &x = f.x, &y = f.y, &n = f.n;
    const double c = f.c, s = f.s;
    dvec3 edge[3];
    for (int k = 0; k < 3; ++k) {
        // The edge opposite face k: along the other two faces, into the solid.
        edge[k] = normal[k];
        if (!perfect) {
            edge[k] = glm::normalize(glm::cross(normal[(k + 1) % 3], normal[(k + 2) % 3]));
            if (glm::dot(edge[k], normal[k]) < 0) edge[k] = -edge[k];
        }
    }
    auto toSheet = [&](const dvec3& w) {
        const double ex = glm::dot(w, x), ey = glm::dot(w, y);
        return dvec3(c * ex - s * ey, s * ex + c * ey, glm::dot(w, n));
    };
    CubeCorner cc;
    for (int k = 0; k < 3; ++k) {
        cc.e[k] = toSheet(normal[k]);
        cc.edge[k] = perfect ? cc.e[k] : toSheet(edge[k]);
    }
    return cc;
}

} // namespace

CubeCorner cube_corner(double cantDeg, double dihedralArcmin, double psi) {
    // The face normals in the cube's frame. With e_k = (a_k + t 1) / |a_k + t 1|,
    // e_i.e_j = (2t + 3t^2) / (1 + 2t + 3t^2) = sin(delta) gives 3t^2 + 2t - q = 0,
    // q = sin(delta) / (1 - sin(delta)).
    dvec3 normal[3];
    const double sinDelta = std::sin(dihedralArcmin * kArcmin);
    const double q = sinDelta / (1.0 - sinDelta);
    const double t = q / (1.0 + std::sqrt(1.0 + 3.0 * q)); // (-2 + sqrt(4 + 12 q)) / 6
    for (int k = 0; k < 3; ++k) {
        normal[k] = dvec3(0.0);
        normal[k][k] = 1.0;
        if (dihedralArcmin != 0.0) normal[k] = glm::normalize(normal[k] + dvec3(t));
    }
    return corner_of_normals(cantDeg, normal, dihedralArcmin == 0.0, psi);
}

CubeCorner cube_corner(double cantDeg, const double dihedralArcmin[3], double psi) {
    dvec3 normal[3];
    gram_normals(dihedralArcmin, normal);
    return corner_of_normals(cantDeg, normal, false, psi);
}

CubeCorner canted_cube_corner(double cantDeg, double psi) {
    return cube_corner(cantDeg, 0.0, psi);
}

PrismOutcome trace_cube_corner(const Sheet& sheet, const CubeCorner& cc, const dvec3& d0, Rng& rng,
                               dvec3* exit) {
    if (!(d0.z < 0)) return kPrismMiss;
    // Uniform entry point: barycentric weights of the aperture's vertices e_k / e_k.z.
    double u = rng.uniform(), v = rng.uniform();
    if (u + v > 1.0) {
        u = 1.0 - u;
        v = 1.0 - v;
    }
    dvec3 x = u * cc.edge[0] / cc.edge[0].z + v * cc.edge[1] / cc.edge[1].z +
              std::max(0.0, 1.0 - u - v) * cc.edge[2] / cc.edge[2].z;
    dvec3 d = d0;
    int reflections = 0;
    while (reflections < 4) {
        // Inside the convex solid the nearest plane ahead is where the ray meets its boundary:
        // the aperture z = 1 (upward rays) or a face.
        int face = -1;
        double tHit =
            d.z > 0 ? std::max(0.0, 1.0 - x.z) / d.z : std::numeric_limits<double>::infinity();
        for (int k = 0; k < 3; ++k) {
            const double toward = glm::dot(d, cc.e[k]);
            const double tk = toward < 0 ? std::max(0.0, glm::dot(x, cc.e[k])) / -toward
                                         : std::numeric_limits<double>::infinity();
            if (tk < tHit) {
                tHit = tk;
                face = k;
            }
        }
        if (face < 0) break; // through the aperture (or nowhere to go)
        x += tHit * d;
        x -= glm::dot(x, cc.e[face]) * cc.e[face]; // on the face plane
        const double cosK = -glm::dot(d, cc.e[face]);
        if (const PrismOutcome lost = face_loss(sheet, cosK, rng); lost != kPrismRetro) return lost;
        d += 2.0 * cosK * cc.e[face];
        ++reflections;
    }
    if (reflections != 3) return kPrismMiss;
    if (exit) *exit = sheet.dihedral_arcmin != 0.0 || sheet.dihedral_spread_arcmin != 0.0 ? d : -d0;
    return kPrismRetro;
}

FullCubeArray full_cube_array(const double dihedralArcmin[3], double psi) {
    FullCubeArray array;
    gram_normals(dihedralArcmin, array.e);
    const SheetFrame f = sheet_frame(0.0, psi);
    // The sheet's axes: the vectors w with (c w.x - s w.y, s w.x + c w.y, w.n) a unit axis.
    array.axis[0] = f.c * f.x - f.s * f.y;
    array.axis[1] = f.s * f.x + f.c * f.y;
    array.axis[2] = f.n;
    return array;
}

PrismOutcome trace_full_cube(const Sheet& sheet, const FullCubeArray& array, const dvec3& d0,
                             Rng& rng, dvec3* exit) {
    if (!(d0.z < 0)) return kPrismMiss;
    // Entry: a uniform point of one period of the lattice of apexes (spanned by (1,-1,0) and
    // (0,1,-1)) on the plane x + y + z = 2, the top of the surface; its cell is plastic (the
    // floors of a point with x + y + z = 2 sum to more than -1).
    const double u = rng.uniform(), v = rng.uniform();
    dvec3 x = dvec3(2.0 / 3.0) + u * dvec3(1.0, -1.0, 0.0) + v * dvec3(0.0, 1.0, -1.0);
    glm::ivec3 cell(int(std::floor(x.x)), int(std::floor(x.y)), int(std::floor(x.z)));
    dvec3 d = d0.x * array.axis[0] + d0.y * array.axis[1] + d0.z * array.axis[2];
    int hits[3] = {0, 0, 0};
    bool out = false;
    for (int step = 0; step < kMaxFullCubeSteps && !out; ++step) {
        // The cell's nearest boundary ahead.
        int axis = -1;
        double tHit = std::numeric_limits<double>::infinity();
        for (int k = 0; k < 3; ++k) {
            if (d[k] == 0.0) continue;
            const double boundary = d[k] > 0 ? cell[k] + 1.0 : double(cell[k]);
            const double t = std::max(0.0, (boundary - x[k]) / d[k]);
            if (t < tHit) {
                tHit = t;
                axis = k;
            }
        }
        if (axis < 0) break;
        x += tHit * d;
        x[axis] = d[axis] > 0 ? cell[axis] + 1.0 : double(cell[axis]);
        glm::ivec3 next = cell;
        next[axis] += d[axis] > 0 ? 1 : -1;
        if (next.x + next.y + next.z >= 0) {
            // Plastic ahead; above x + y + z = 3 an upward ray meets no face again.
            cell = next;
            out = cell.x + cell.y + cell.z >= 3 && d.x + d.y + d.z > 0;
            continue;
        }
        // Air ahead: the face x[axis] = cell[axis] of the cube whose apex is the cell's corner.
        const dvec3& e = array.e[axis];
        const double cosK = -glm::dot(d, e);
        if (!(cosK > 0)) return kPrismMiss; // a turned normal that the ray grazes
        if (const PrismOutcome lost = face_loss(sheet, cosK, rng); lost != kPrismRetro) return lost;
        d += 2.0 * cosK * e;
        ++hits[axis];
    }
    if (!out) return kPrismMiss;
    if (exit)
        *exit = dvec3(glm::dot(d, array.axis[0]), glm::dot(d, array.axis[1]),
                      glm::dot(d, array.axis[2]));
    return (hits[0] & hits[1] & hits[2] & 1) ? kPrismRetro : kPrismMiss;
}

} // namespace sim
} // namespace retroprism
