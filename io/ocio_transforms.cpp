#include "ocio_transforms.h"

#include <stdexcept>
#include <string>

namespace retroprism::ocio {

Mat3 mul(const Mat3& a, const Mat3& b) {
    Mat3 c{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k)
                c[size_t(i)][size_t(j)] += a[size_t(i)][size_t(k)] * b[size_t(k)][size_t(j)];
    return c;
}

Mat3 inverse(const Mat3& m) {
    const double a = m[0][0], b = m[0][1], c = m[0][2], d = m[1][0], e = m[1][1], f = m[1][2],
                 g = m[2][0], h = m[2][1], i = m[2][2];
    const double A = e * i - f * h, B = -(d * i - f * g), C = d * h - e * g;
    const double det = a * A + b * B + c * C;
    return {{{A / det, -(b * i - c * h) / det, (b * f - c * e) / det},
             {B / det, (a * i - c * g) / det, -(a * f - c * d) / det},
             {C / det, -(a * h - b * g) / det, (a * e - b * d) / det}}};
}

Mat3 rgb_to_xyz(const double xy[3][2], const double white[2]) {
    Mat3 P;
    for (int k = 0; k < 3; ++k) {
        const double x = xy[k][0], y = xy[k][1];
        P[0][size_t(k)] = x / y;
        P[1][size_t(k)] = 1.0;
        P[2][size_t(k)] = (1.0 - x - y) / y;
    }
    const double W[3] = {white[0] / white[1], 1.0, (1.0 - white[0] - white[1]) / white[1]};
    const Mat3 Pi = inverse(P);
    double S[3];
    for (int k = 0; k < 3; ++k)
        S[k] = Pi[size_t(k)][0] * W[0] + Pi[size_t(k)][1] * W[1] + Pi[size_t(k)][2] * W[2];
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            P[size_t(i)][size_t(k)] *= S[k];
    return P;
}

OCIO::MatrixTransformRcPtr matrix(const Mat3& m) {
    double M[16] = {m[0][0], m[0][1], m[0][2], 0, m[1][0], m[1][1], m[1][2], 0,
                    m[2][0], m[2][1], m[2][2], 0, 0,       0,       0,       1};
    OCIO::MatrixTransformRcPtr t = OCIO::MatrixTransform::Create();
    t->setMatrix(M);
    return t;
}

OCIO::TransformRcPtr srgb_curve(OCIO::TransformDirection dir) {
    OCIO::ExponentWithLinearTransformRcPtr t = OCIO::ExponentWithLinearTransform::Create();
    const double g[4] = {2.4, 2.4, 2.4, 1.0}, o[4] = {0.055, 0.055, 0.055, 0.0};
    t->setGamma(g);
    t->setOffset(o);
    t->setDirection(dir); // forward: encoded -> linear
    return t;
}

OCIO::TransformRcPtr power(double gamma) {
    OCIO::ExponentTransformRcPtr t = OCIO::ExponentTransform::Create();
    const double g[4] = {gamma, gamma, gamma, 1.0};
    t->setValue(g); // forward: encoded -> linear
    return t;
}

OCIO::TransformRcPtr builtin(const char* style, OCIO::TransformDirection dir) {
    OCIO::BuiltinTransformRcPtr t = OCIO::BuiltinTransform::Create();
    t->setStyle(style);
    t->setDirection(dir);
    return t;
}

OCIO::TransformRcPtr to_rec709(const double primaries[3][2]) {
    return matrix(mul(inverse(rgb_to_xyz(kRec709, kD65)), rgb_to_xyz(primaries, kD65)));
}

OCIO::ConstCPUProcessorRcPtr cpu(const OCIO::ConstTransformRcPtr& t) {
    try {
        static const OCIO::ConstConfigRcPtr config = OCIO::Config::CreateRaw();
        return config->getProcessor(t)->getDefaultCPUProcessor();
    } catch (const OCIO::Exception& e) {
        throw std::runtime_error(std::string("OpenColorIO: ") + e.what());
    }
}

} // namespace retroprism::ocio
