// openmaterial.h: ASAM OpenMATERIAL 3D files, read and written: the BRDF look-up table
// (`NAME_brdf.xompt`) and the material file (`NAME.xomp`).
//
// What the fields mean, from the format's JSON schemas (material_brdf_schema.json and
// material_schema.json, as the ASAM checker bundle qc-openmaterial-3d ships them), versions 1.0.0
// and 1.1.0; 1.1.0 adds brdf.receiverSolidAngles. The files written declare 1.0.0 and are
// validated against its schemas (tests/data/openmaterial/, [python]):
//  - metadata: name, uuid (8-4-4-4-12 hexadecimal), materialVersion and openMaterial3dVersion
//    (semantic versions), copyrights and authors (arrays of at least one string), license;
//    the table also requires `sources` (measured, simulated or from literature), and may say
//    typicalSensorTechnology ("lidar").
//  - brdf.wavelengths: every wavelength of the table, m, each in [1e-9, 17.16e-3].
//  - brdf.lookupTable: rows [wavelength m, theta_i rad in [0, pi/2], theta_o rad in [0, pi/2],
//    phi_o rad in [0, 2 pi], f 1/sr >= 0], sorted by the columns starting with the first.
//    theta_i and theta_o from the surface normal; phi_o the exit azimuth relative to the
//    incident one (the incident direction at azimuth 0). One incident azimuth only: the table
//    describes an isotropic surface (a material that is not is averaged over its orientation).
//  - brdf.receiverSolidAngles (optional): per wavelength the receiver's solid angle (sr) the
//    values were measured with (for very retroreflective materials, where the value depends on it).
//  - materialProperties.retroreflectivityData: coefficientOfRetroreflection in cd lx^-1 m^-2,
//    in [0, 5000], "in the visible light spectrum", with its sources.
//  - materialProperties.brdfUris: relative paths of BRDF tables, each ending in `_brdf.xompt`.
// Directions here point away from the surface (the node's convention): the retro direction is
// theta_o = theta_i, phi_o = 0; the mirror direction theta_o = theta_i, phi_o = pi.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace retroprism {

struct OpenMaterialMetadata {
    std::string name;
    std::string description;
    std::string uuid;
    std::string material_version = "1.0.0";
    std::string openmaterial_version = "1.0.0";
    std::vector<std::string> copyrights;
    std::string license;
    std::vector<std::string> authors;
    std::string sources;
    std::string sensor_technology; // typicalSensorTechnology; empty: left out
};

struct ReceiverSolidAngle {
    double wavelength = 0;  // m
    double solid_angle = 0; // sr
};

// A BRDF table, its rows as read (sorted), with an index for interpolation.
struct BrdfTable {
    OpenMaterialMetadata metadata;
    std::vector<double> wavelengths; // m
    std::vector<ReceiverSolidAngle> receiver_solid_angles;
    std::vector<std::array<double, 5>> rows; // wavelength, theta_i, theta_o, phi_o, f
};

// Reads and checks a table from its JSON; every error is an InputError "SOURCE: FIELD: ..."
// naming the field by its JSON path (e.g. brdf.lookupTable[12][1]) and the allowed form or range:
// a missing required field, a wrong type, a value outside the schema's range, a null entry (the
// schema allows them; their meaning is not defined, so they are not read), rows out of order or
// repeated, a row's wavelength not among `wavelengths`, an empty table.
BrdfTable parse_brdf_table(const nlohmann::json& j, const std::string& source);
BrdfTable read_brdf_table(const std::string& path);

// The table as JSON text (rows with 9 significant digits), and the material file referring to
// it, with the coefficient of retroreflection and its sources.
std::string brdf_table_json(const BrdfTable& t);
std::string material_json(const OpenMaterialMetadata& m, double coefficientOfRetroreflection,
                          const std::string& raSources, const std::vector<std::string>& brdfUris);

// A UUID (8-4-4-4-12 hexadecimal, version 5 style bits) from the bytes of `text` (FNV-1a based,
// deterministic): the same inputs give the same UUID.
std::string uuid_from(const std::string& text);

// f at (wavelength, theta_i, theta_o, phi_o) by linear interpolation through the table's sorted
// hierarchy: between the two rows' theta_i bracketing theta_i, in each between the two theta_o,
// in each between the two phi_o (periodic over 2 pi); outside a column's range, its end. The
// wavelength must be one of the table's (within 1e-9 relative); otherwise nothing.
std::optional<double> brdf_table_value(const BrdfTable& t, double wavelength, double thetaI,
                                       double thetaO, double phiO);

} // namespace retroprism
