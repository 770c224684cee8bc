// cube_corner.h: cube corners other than the paper's in the simulator: canted ones (MODEL.md
// section 8) and ones whose dihedral angles differ from 90 degrees (docs/dihedral.md): the
// prism's faces in the sheet's frame, built from the cube's own frame, and the exact trace of a
// ray through it, face by face. The paper's perfect cube (cant 0, no dihedral error) is traced by
// trace_prism itself.
#pragma once

#include "microgeometry.h"

namespace retroprism {
namespace sim {

// A trihedral corner below the sheet: apex at the origin, face k the plane x.e_k = 0 (e_k unit,
// e_k.z > 0), the solid {x.e_k >= 0}, aperture the triangle the plane z = 1 cuts from it, with
// vertices edge_k / edge_k.z: edge_k is the unit direction of the solid's edge opposite face k
// (where the other two faces meet), e_k itself when the faces are mutually perpendicular.
struct CubeCorner {
    dvec3 e[3];
    dvec3 edge[3];
};

// The corner of cant `cantDeg`, dihedral error `dihedralArcmin` and orientation `psi` (radians).
// In the cube's frame the perfect faces are x = 0, y = 0, z = 0 (normals the unit axes a_k) and
// the sheet normal is n = normalize(a cos(cant) + u sin(cant)), a = (1,1,1) / sqrt3, u the unit
// vector perpendicular to a toward e_1; the sheet's frame has n as +z and the projection of e_1
// at azimuth psi. A dihedral error delta opens each of the three dihedral angles to
// 90 degrees + delta: every face turns about its edge in the aperture (the axis a_k x a), its
// normal tilting toward the cube axis, e_k = normalize(a_k + t (1,1,1)) with t such that
// e_i.e_j = sin(delta) (the interior angle between faces i and j is 180 degrees minus the angle
// between their inward normals).
CubeCorner cube_corner(double cantDeg, double dihedralArcmin, double psi);

// The corner whose three dihedral angles differ: 90 degrees + dihedralArcmin[k] between the two
// faces other than k. The inward normals have the Gram matrix G,
// G_ij = sin(error between i and j), and are e = G^(1/2) applied to the axes (the symmetric
// square root: the normals nearest the axes, e_k = normalize(a_k + t (1,1,1)) when the three
// errors are equal); the cant, the sheet's frame and the aperture as above. Errors may be
// negative (angles below 90 degrees).
CubeCorner cube_corner(double cantDeg, const double dihedralArcmin[3], double psi);

// An array of full cube corners (hexagonal apertures, cant 0), the back surface of a sheet whose
// cubes are not truncated: in the cube's frame the plastic is the union of the unit cells
// [i, i+1] x [j, j+1] x [k, k+1] with i + j + k >= 0 and the air below it the cells with
// i + j + k <= -1, so that every lattice point with i + j + k = 0 is the apex of a cube corner
// whose faces are the three unit squares x = i, y = j, z = k that meet there (seen along the
// axis a = (1,1,1) / sqrt3, the sheet normal, each aperture a regular hexagon, the surface
// between heights 0 and 2 / sqrt3 along a). A ray may meet faces of neighbouring cubes: the trace
// walks the cells along it (a 3D digital differential analyser) and reflects wherever the next
// cell is air. Dihedral errors turn each face's reflection normal as for the truncated corner
// (the Gram-matrix normals, the same for every cube); the faces keep their place (a shift of
// order delta times the cube's size, which moves no exit direction).
struct FullCubeArray {
    dvec3 e[3];    // reflection normals of the faces x = i, y = j, z = k, in the cube's frame
    dvec3 axis[3]; // the sheet frame's axes (x, y, z = the normal) in the cube's frame
};

// The array of orientation `psi` (the projection of the cube's x axis at azimuth psi in the
// sheet's frame, as for cube_corner) and per-face dihedral errors.
FullCubeArray full_cube_array(const double dihedralArcmin[3], double psi);

// A downward ray of direction d (sheet frame, unit, d.z < 0) enters the sheet at a uniform point
// and is traced through the array with the sheet's face reflectance (as trace_cube_corner). It is
// retroreflected when it leaves after an odd number of reflections on each of the three face
// orientations (the product of the reflections is then -I for perfect faces, whichever cubes it
// met), else a miss; `exit` (when not null) receives the traced exit direction of either, in the
// sheet's frame. A ray still below the surface after kMaxFullCubeSteps cells, or grazing a turned
// face, is a miss without an exit direction.
constexpr int kMaxFullCubeSteps = 10000;
PrismOutcome trace_full_cube(const Sheet& sheet, const FullCubeArray& array, const dvec3& d,
                             Rng& rng, dvec3* exit = nullptr);

// The perfect (90-degree) canted corner: cube_corner(cantDeg, 0, psi).
CubeCorner canted_cube_corner(double cantDeg, double psi);

// A downward ray of direction d (unit, d.z < 0) enters the aperture at a uniform point and is
// traced face by face with the sheet's face reflectance (as trace_prism). A ray that leaves
// after one reflection on each face is retroreflected; `exit` (when not null) receives its
// direction: the traced one with dihedral errors (sheet.dihedral_arcmin or
// sheet.dihedral_spread_arcmin not 0), else exactly -d.
PrismOutcome trace_cube_corner(const Sheet& sheet, const CubeCorner& cc, const dvec3& d, Rng& rng,
                               dvec3* exit = nullptr);

} // namespace sim
} // namespace retroprism
