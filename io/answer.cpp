#include "answer.h"

namespace retroprism {

template <class Real>
std::vector<BackendResult> evaluate_node(const Params& p, const std::vector<DirectionPair>& pairs) {
    using Node = PrismaticRetroreflector<Real>;
    using vec3 = typename Node::vec3;
    const Node node(p);
    auto rgb = [](const vec3& v) {
        return std::array<double, 3>{double(v.x), double(v.y), double(v.z)};
    };
    std::vector<BackendResult> out;
    out.reserve(pairs.size());
    for (const DirectionPair& s : pairs) {
        const vec3 wi(Real(s.wi[0]), Real(s.wi[1]), Real(s.wi[2]));
        const vec3 wo(Real(s.wo[0]), Real(s.wo[1]), Real(s.wo[2]));
        const typename Node::Eval e = node.eval(wi, wo);
        out.push_back(
            {rgb(e.f.total()), rgb(e.f.surface), rgb(e.f.retro), rgb(e.f.diffuse), double(e.pdf)});
    }
    return out;
}

template std::vector<BackendResult> evaluate_node<float>(const Params&,
                                                         const std::vector<DirectionPair>&);
template std::vector<BackendResult> evaluate_node<double>(const Params&,
                                                          const std::vector<DirectionPair>&);

} // namespace retroprism
