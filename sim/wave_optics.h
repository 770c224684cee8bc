// wave_optics.h: the simulator's physical-optics ground truth (docs/wave_optics.md): the exit
// pupil of one cube corner traced face by face (six face orders, each a convex polygon with its
// Jones matrix, optical path and exit direction), its Fraunhofer far field in closed form (the
// Fourier transform of a polygon as a sum over its edges) and, independently, by FFT of the
// sampled pupil (FFTW3), and the coefficient of retroreflection R_A averaged over prism
// orientations, observation azimuth and wavelengths (illuminant A x V(lambda)).
//
// Conventions (written once here):
//  - Sheet frame: normal +z, as cube_corner.h. wi: unit, toward the light (wi.z > 0); the light
//    travels along -wi, refracts at the smooth flat top surface (index eta against air), meets
//    the cube corner, and leaves upward. Lengths in micrometres, wavelengths in micrometres
//    inside (nm at the API's edges).
//  - Fields: complex amplitudes of time dependence exp(-i omega t), plane waves exp(+i k.x);
//    a far-field amplitude U(s) = integral of the exit field times exp(-i k0 s_xy.x) over the
//    sheet plane, so a plane wave of transverse direction g peaks at s_xy = g. Absorbing media
//    have Im(n) > 0.
//  - Polarisation: a wave of direction k meeting a surface of normal n has s = normalize(k x n)
//    (the +y axis when k is along n) and p = s x k, for incident, reflected and transmitted
//    waves alike; Fresnel amplitudes in that convention are Born & Wolf's (section 1.5.2), a
//    perfect mirror has r_s = -1, r_p = +1. Unpolarised light: the mean over the inputs s and p.
//  - R_A = cos(theta_i) cos(theta_o) I(s) / (lambda^2 A_cell) in sr^-1 (cd lx^-1 m^-2), I the
//    sum over output components of |U|^2 for a unit incident amplitude, A_cell the area of the
//    prism's aperture triangle: then the integral of R_A over observation directions divided by
//    cos(theta_i) is the retroreflected fraction of the light falling on the cell (Parseval).
#pragma once

#include <array>
#include <complex>
#include <vector>

#include "cube_corner.h"
#include "photopic.h"

namespace retroprism {
namespace sim {
namespace wave {

using cplx = std::complex<double>;
using dvec2 = glm::dvec2;

// ---- Polygons and their Fourier transform ---------------------------------------------------

// A convex polygon in the sheet plane, vertices counter-clockwise.
using Polygon = std::vector<dvec2>;

double polygon_area(const Polygon& p);
double polygon_perimeter(const Polygon& p);
dvec2 polygon_centroid(const Polygon& p);

// The part of `p` where the affine function with values `f` at its vertices is >= 0
// (Sutherland-Hodgman against one half-plane; exact for an affine f).
Polygon clip_polygon(const Polygon& p, const std::vector<double>& f);

// F(k) = integral over the polygon of exp(-i k.x) d^2x. Lee & Mittra (1983); by the divergence
// theorem F = (i/|k|^2) sum_j (k.n_j) L_j exp(-i k.m_j) sinc(k.D_j/2) (outward normal n_j,
// length L_j, midpoint m_j, edge vector D_j), about the centroid; for |k| R < 1 (R the largest
// distance of a vertex from the centroid), where that sum cancels, the fan of triangles about
// the centroid by the power series of each triangle's transform. F(0) = area.
struct PolygonTransform {
    explicit PolygonTransform(const Polygon& p);
    cplx operator()(const dvec2& k) const;

    double area = 0;
    double radius = 0; // largest distance of a vertex from the centroid
    dvec2 centroid{0.0};
    Polygon about; // vertices relative to the centroid
};

// ---- Fresnel amplitudes ---------------------------------------------------------------------

// Amplitude coefficients of a plane wave in a medium of index n1 (real) meeting one of index n2
// at cosThetaI (Born & Wolf 1.5.2; cos(theta_t) complex, its branch Im(n2 cos theta_t) >= 0: the
// evanescent wave of total internal reflection decays; TIR gives |r_s| = |r_p| = 1 and their
// phases, B&W 1.5.4 Eq. 60).
struct Fresnel {
    cplx rs, rp, ts, tp, cosT;
};
Fresnel fresnel(double cosThetaI, double n1, cplx n2);

// The face reflectance modes (sim/microgeometry.h's prism_reflection).
enum class Face { kIdeal = 0, kTir = 1, kMetal = 2 };

// A plane wave's complex field vector after a surface of unit normal `normal` (pointing to the
// incident side, k.normal < 0): reflected (kIdeal: a perfect mirror; kTir: against air (n2 = 1);
// kMetal: against index `metal`), or transmitted into index n2 (real, no TIR). `k` becomes the
// new direction (real: transmission below the critical angle only).
using Field = std::array<cplx, 3>;
Field reflect_field(const Field& e, dvec3& k, const dvec3& normal, double n1, Face face,
                    cplx metal);
Field transmit_field(const Field& e, dvec3& k, const dvec3& normal, double n1, double n2);

// s and p of a wave of direction k at a surface of normal n (the conventions above).
void sp_basis(const dvec3& k, const dvec3& n, dvec3& s, dvec3& p);

// The metal of a metallized face: aluminium's index shape, N = a (0.958 + 6.69 i) / 6.69
// (Rakic 1995 at 550 nm: a = 6.69), its scale a >= 3 chosen so that the unpolarised
// reflectance inside index eta at incidence acos(1/sqrt3) = 54.74 degrees (the faces of the
// uncanted cube at normal incidence) is `reflectance` (0.88 at eta 1.49: N = 0.98 + 6.87 i).
// Below what a = 3 gives (0.80 at eta 1.49), which no aluminium coat has, an absorbing
// dielectric N = eta + i kappa with that reflectance. Throws InputError naming
// metal_reflectance unless it is in [0, 1).
cplx metal_index(double reflectance, double eta);

// ---- The exit pupil of one cube corner ------------------------------------------------------

// The material of the prisms (no roughness: a smooth flat top surface).
struct WaveMaterial {
    double ior = 1.49;
    int prism_reflection = 1;        // 0 ideal, 1 tir, 2 metallized
    double metal_reflectance = 0.88; // metallized: the face reflectance at 54.74 degrees
    double cant_deg = 0.0;           // cube_corner's cant
    double dihedral_arcmin = 0.0;    // cube_corner's dihedral error, all three angles
    // Or per face: the error between the two faces other than k (cube_corner's overload), when
    // any is not 0 (dihedral_arcmin must then be 0).
    std::array<double, 3> dihedral_faces_arcmin{0.0, 0.0, 0.0};
    // The groove spacing in micrometres: the height of the aperture triangle of the truncated
    // cube corner over its edge in face 1 (the quantity patents quote; for cant 0 all three
    // heights). A_cell is the triangle's area: pitch^2 / sqrt3 for cant 0.
    double pitch_um = 150.0;
};

// The material of the node's parameters (ior, prism_reflection, metal_reflectance, cant_angle,
// dihedral_error) with the groove spacing `pitchUm`.
WaveMaterial wave_material(const Params& p, double pitchUm);

// The material's corner at orientation psi (radians), cube_corner's.
CubeCorner wave_corner(const WaveMaterial& m, double psi);

// Throws InputError naming the field and its range unless: ior in [1, 3], prism_reflection in
// {0, 1, 2}, metal_reflectance valid for metal_index (metallized), cant in [-30, 30] degrees,
// dihedral errors in [-60, 60] arcmin (per face or all three, not both), pitch in [1, 1e5] um.
void check_material(const WaveMaterial& m);

// One face order: the entry points whose ray meets faces[0], faces[1], faces[2] in turn and
// leaves through the aperture.
struct Order {
    std::array<int, 3> faces{};
    Polygon entry, exit;   // entry points, and where they leave (sheet plane, um)
    dvec3 inner_exit{0.0}; // direction inside after the third reflection
    dvec3 exit_dir{0.0};   // outside, after refraction at the top surface
    dvec2 g{0.0};          // exit_dir.xy: the transverse direction of the order's plane wave
    // The exit field (outside, unit incident amplitude) for the inputs s and p: column c is the
    // field vector for input c; `jones` the same in the exit wave's (s, p) basis, [out][in].
    std::array<Field, 2> field{};
    std::array<std::array<cplx, 2>, 2> jones{};
    // Phase of the exit field at exit point x: phase + k0 g.x (k0 = 2 pi / lambda), the optical
    // path from the incident wave's phase at the origin of the sheet plane; vertex_phase: the
    // same traced to each exit vertex (equal to it: the exit wavefront is plane).
    double phase = 0;
    std::vector<double> vertex_phase;
};

struct Pupil {
    std::vector<Order> orders; // those of positive area
    double cell_area = 0;      // A_cell (um^2)
    double lambda_um = 0.55;
    dvec3 wi{0, 0, 1};
    dvec3 d{0, 0, -1};     // refracted direction inside
    double ts = 0, tp = 0; // entrance power transmittances |t|^2 eta cos_t / cos_i (s, p)
    Polygon aperture;      // the aperture triangle (um)
};

// The aperture scale: micrometres per unit of cube_corner's aperture (z = 1) for `pitch_um`.
double aperture_scale(const CubeCorner& cc, double pitchUm);

// The exit pupil of corner `cc` (cube_corner's, scaled to the material's pitch) lit from wi.
Pupil exit_pupil(const WaveMaterial& m, const CubeCorner& cc, const dvec3& wi, double lambdaUm);

// The retroreflected fraction of the light falling on the cell: sum over orders of the exit
// polygon's area times the mean over inputs of |field|^2, over A_cell (includes the top
// surface's transmittances both ways).
double pupil_energy(const Pupil& pupil);

// ---- Far field ------------------------------------------------------------------------------

// A pupil's orders' transforms, prepared once for many observation directions.
struct FarField {
    explicit FarField(const Pupil& pupil);
    // U(s) for the observation direction's transverse components s_xy: [input][component].
    std::array<Field, 2> amplitude(const dvec2& sxy) const;
    // The mean over the inputs s and p of the sum over components of |U|^2 (um^4).
    double intensity(const dvec2& sxy) const;
    // R_A (sr^-1) toward the unit direction wo.
    double ra(const dvec3& wo) const;

    Pupil pupil; // a copy: a FarField may outlive the pupil it was made from
    std::vector<PolygonTransform> transforms;
    double k0 = 0;
};

// R_A on an n x n grid of observation directions about wi: s_xy = wi_xy + (u, v), u and v the
// cell centres of [-half, half] (half = halfWidthDeg in radians of transverse direction),
// row-major with v the row: the 2D far field of one prism (n in [1, 4096]).
std::vector<double> far_field_grid(const Pupil& pupil, int n, double halfWidthDeg);

// The direction at angle `observationRad` from wi, at azimuth chi about it: chi = 0 toward
// a = normalize(z - wi (wi.z)) (in the plane of incidence, toward the normal; +x at normal
// incidence), chi = pi/2 toward b = wi x a.
dvec3 observation_direction(const dvec3& wi, double observationRad, double chi);

// The azimuth-averaged tail of one coherent polygon of uniform field (Fraunhofer, |k| large):
// `<R_A>` -> cos(theta_o) lambda P_eff / (4 pi^3 theta^3 A_cell) times the field's |J|^2, with
// P_eff = sum_j L_j sqrt((n_j.a)^2 / cos^2(theta_i) + (n_j.b)^2) (a, b as above, projected on the
// sheet plane): the perimeter of the polygon seen from the light, over cos(theta_i)
// (docs/wave_optics.md derives it). Returns P_eff.
double tail_perimeter(const Polygon& p, const dvec3& wi);

// The same for a whole pupil of perfect cubes (every order with the same g): the edges' spikes
// add per line of the sheet plane, with the jump of the field across it (the difference of the
// orders' fields on either side, zero outside): `<R_A>` -> cos(theta_o) lambda K / (4 pi^3
// theta^3 A_cell), K = sum over lines of rho_line times the integral along the line of the mean
// over the inputs of |jump|^2, rho = sqrt((n.a)^2 / cos^2(theta_i) + (n.b)^2). For ideal faces
// the jumps between orders vanish and K = P_eff (Ts^2 + Tp^2) / 2; TIR orders add their
// internal edges. Returns K (um).
double tail_constant(const Pupil& pupil);

// ---- FFT of the sampled pupil ---------------------------------------------------------------

// The far field by FFT: the pupil's field (each order's polygon with its field, phase and
// carrier relative to `g_ref`, the mean of the orders' g weighted by area) integrated exactly
// over square cells of side h (each polygon's coverage of a cell by clipping), zero-padded to
// `size` x `size`, transformed by FFTW3, divided by the cell's transform sinc(q_x h/2)
// sinc(q_y h/2). Its samples are at q = (i, j) dq, dq = 2 pi / (size h), |i|, |j| < size / 2,
// with q = k0 (s_xy - g_ref).
struct FftFarField {
    int size = 0;
    double h = 0, dq = 0, k0 = 0;
    dvec2 g_ref{0.0};
    double ra_scale = 0;           // R_A = ra_scale * intensity (the cos factors at g_ref)
    std::vector<double> intensity; // [(j + size/2) * size + (i + size/2)], as FarField's
    double at(int i, int j) const {
        return intensity[size_t((j + size / 2) * size + i + size / 2)];
    }
};
// `cellsAcross`: cells over the pupil's larger extent; `pad`: size = pad * cellsAcross rounded
// up to a power of two. Throws InputError unless cellsAcross in [8, 4096] and pad in [2, 64].
// Thread-safe (FFTW's planner behind a lock). ra_scale is exact at g_ref only; the tests compare
// intensities.
FftFarField fft_far_field(const Pupil& pupil, int cellsAcross, int pad);

// ---- R_A of the sheet -----------------------------------------------------------------------

// Which prism orientations are summed (incoherently, each the prism's own cell):
//  - kAveraged: uniform over the period (120 degrees for cant 0, else 360), by the midpoint rule
//    with `orientations` nodes over half of it (the mirror symmetry, wave_ra.cpp; unequal
//    per-face errors break both symmetries: 360 degrees, 2 orientations nodes); the
//    integrand has kinks (faces entering TIR, the ERA polygon changing its vertices), so the
//    rule converges as 1/N^2 (tests/sim/test_wave.cpp measures it);
//  - kMatchedPair: the prism at each rotation and its copy turned by 180 degrees;
//  - kOriented: the prism at each rotation.
// Rotation epsilon turns the prism about the normal (counter-clockwise seen from +z: psi =
// epsilon in cube_corner, photometry.h's rotation angle). Observation: the mean over the
// observation azimuth about wi (the default), or the one coplanar direction of
// analysis/photometry.h's ra_directions, wo = (sin(beta - alpha), 0, cos(beta - alpha)).
struct WaveMode {
    enum class Era { kAveraged, kMatchedPair, kOriented };
    Era era = Era::kAveraged;
    std::vector<double> rotations_deg{0.0};
    bool coplanar = false;
    int orientations = 64; // kAveraged's nodes over half the period
    // Observation-azimuth nodes per k0 theta D (D the aperture's largest side): |U|^2 on that
    // circle holds harmonics up to about k0 theta D, so 2 resolve it (the trapezoidal rule is
    // then exact to rounding: the test measures 2 against 4).
    double azimuth_density = 2.0;
    // Prisms of several sizes (moulding tolerances): pitches uniform by number over
    // pitch_um (1 +- pitch_spread), pitch_spread in [0, 0.5], by the midpoint rule with
    // pitch_nodes nodes; each pitch's R_A weighted by its cell area (R_A is per unit of sheet).
    // R_A(alpha; pitch, lambda) = (pitch/lambda)^2 G(alpha pitch / lambda) without dispersion,
    // so a spread of pitches acts as a band of wavelengths: it washes out the rings of one size.
    double pitch_spread = 0.0;
    int pitch_nodes = 16;
};

// The mode of the node's era_mode (matched_pair and oriented at its orientation).
WaveMode wave_mode(const Params& p);

// R_A (sr^-1) of the prisms alone at entrance `entranceDeg` (signed: wi = (sin, 0, cos)) for each
// observation angle (degrees, in (0, 20]) at wavelength lambdaNm in [200, 20000]. Throws
// InputError naming the argument and its range.
std::vector<double> wave_ra_profile(const WaveMaterial& m, double entranceDeg,
                                    const std::vector<double>& observationDeg, double lambdaNm,
                                    const WaveMode& mode = WaveMode());
double wave_ra(const WaveMaterial& m, double entranceDeg, double observationDeg, double lambdaNm,
               const WaveMode& mode = WaveMode());

// ---- Photometry -----------------------------------------------------------------------------

// The photometric weighting (util/photopic.h), under the names the simulator has used.
using retroprism::illuminant_a;
using retroprism::photopic_v;
using retroprism::photopic_wavelengths_nm;
using retroprism::photopic_weights;
// R_A weighted by illuminant A x V(lambda) over photopic_wavelengths_nm().
std::vector<double> wave_ra_profile_photometric(const WaveMaterial& m, double entranceDeg,
                                                const std::vector<double>& observationDeg,
                                                const WaveMode& mode = WaveMode());

} // namespace wave
} // namespace sim
} // namespace retroprism
