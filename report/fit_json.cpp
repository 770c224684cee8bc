#include "fit_json.h"

#include "query.h"

namespace retroprism {

using json = nlohmann::ordered_json;

namespace {

json node_json(const NodeFitParams& p) {
    const Params q = node_params(p);
    json j = json::object();
    j["roughness"] = q.roughness;
    j["ior"] = q.ior;
    j["specular"] = q.specular;
    j["retro_color"] = q.retro_color;
    j["diffuse_color"] = q.diffuse_color;
    j["prism_reflection"] =
        enum_values(*find_param("prism_reflection")).at(size_t(p.prism_reflection));
    j["cant_angle"] = q.cant_angle;
    j["dihedral_error"] = q.dihedral_error;
    j["dihedral_spread"] = q.dihedral_spread;
    return j;
}

json mrm_json(const baselines::RetroreflectiveGGX& m) {
    json j = json::object();
    j["roughness"] = m.roughness;
    j["ior"] = m.ior;
    j["specular"] = m.specular;
    j["tint"] = {m.tint.x, m.tint.y, m.tint.z};
    j["color"] = {m.color.x, m.color.y, m.color.z};
    return j;
}

// The table's entry i as JSON: where it was measured and what it measured.
json entry_json(const RaEntry& e) {
    return {{"line", e.line},
            {"observation_deg", e.observation_deg},
            {"entrance_deg", e.entrance_deg},
            {"rotation_deg", e.rotation_deg ? json(*e.rotation_deg) : json()},
            {"presentation_deg", e.presentation_deg},
            {"ra", e.ra}};
}

json mrm_fit_json(const RaMrmFit& mf) {
    return {{"params", mrm_json(mf.model)},
            {"log_rms", mf.report.log_rms},
            {"max_error", mf.report.max_error}};
}

json ra_json(const RaMeasurements& t, const RaNodeFit& nf, const RaMrmFit& mf) {
    json j = json::object();
    j["table"] = t.file;
    j["fitted"] = nf.fitted;
    j["params"] = params_to_json(nf.params);
    j["log_rms"] = nf.report.log_rms;
    j["max_error"] = nf.report.max_error;
    json entries = json::array();
    for (size_t i = 0; i < t.entries.size(); ++i) {
        json e = entry_json(t.entries[i]);
        e["node"] = nf.report.model[i];
        e["node_error"] = nf.report.error[i];
        e["mrm"] = mf.report.model[i];
        e["mrm_error"] = mf.report.error[i];
        entries.push_back(e);
    }
    j["entries"] = entries;
    j["mrm"] = mrm_fit_json(mf);
    return j;
}

} // namespace

json fit_json(const NodeFit& nf, const MrmFit& mf) {
    json j = json::object();
    j["params"] = node_json(nf.params);
    j["rel_rms"] = nf.report.rel_rms;
    j["log_rms"] = nf.report.log_rms;
    j["mrm"] = {{"params", mrm_json(mf.model)},
                {"rel_rms", mf.report.rel_rms},
                {"log_rms", mf.report.log_rms}};
    return j;
}

json ra_fit_json(const RaColoredFit& cf, const RaMrmFit& mf) {
    json j = ra_json(cf.rows, cf.fit, mf);
    for (const RaColorFit& c : cf.colors)
        j["colors"][c.color] = {{"retro_color", c.retro_color},
                                {"log_rms", c.report.log_rms},
                                {"max_error", c.report.max_error}};
    return j;
}

json ra_baseline_json(const RaMeasurements& t, const RaMrmFit& mf) {
    json j = json::object();
    j["table"] = t.file;
    j["mrm"] = mrm_fit_json(mf);
    json entries = json::array();
    for (size_t i = 0; i < t.entries.size(); ++i) {
        json e = entry_json(t.entries[i]);
        e["mrm"] = mf.report.model[i];
        e["mrm_error"] = mf.report.error[i];
        entries.push_back(e);
    }
    j["mrm"]["entries"] = entries;
    return j;
}

} // namespace retroprism
