// cube_corner.h: canted cube corners in the simulator (MODEL.md section 8): the prism's faces in
// the sheet's frame, built from the cube's own frame, and the exact trace of a ray through it.
// The paper's cube (cant 0) is traced by trace_prism itself.
#pragma once

#include "microgeometry.h"

namespace retroprism {
namespace sim {

// A cube corner below the sheet: apex at the origin, face k the plane x.e_k = 0 (e_k unit,
// mutually perpendicular, e_k.z > 0), aperture the triangle the plane z = 1 cuts from the solid
// {x.e_k >= 0}, with vertices e_k / e_k.z.
struct CubeCorner {
    dvec3 e[3];
};

// The cube corner of cant `cantDeg` at orientation `psi` (radians): in the cube's frame the faces
// are x = 0, y = 0, z = 0 and the sheet normal is n = normalize(a cos(cant) + u sin(cant)),
// a = (1,1,1) / sqrt3, u the unit vector perpendicular to a toward e_1; the sheet's frame has n as
// +z and the projection of e_1 at azimuth psi.
CubeCorner canted_cube_corner(double cantDeg, double psi);

// A downward ray of direction d (unit, d.z < 0) enters the aperture at a uniform point and is
// traced face by face with the sheet's face reflectance (as trace_prism).
PrismOutcome trace_cube_corner(const Sheet& sheet, const CubeCorner& cc, const dvec3& d, Rng& rng);

} // namespace sim
} // namespace retroprism
