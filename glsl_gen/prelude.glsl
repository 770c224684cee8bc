// GLSL prelude of the math core: the special functions GLSL lacks. (The C++ prelude maps the
// same names to std::erf, std::erfc and a Newton-refined erfinv.)

// erfc by the Chebyshev fit of Numerical Recipes (Press et al. 2007, Sec. 6.2.2, "erfcc"):
// fractional error below 1.2e-7 for every x.
float rp_erfc(float x) {
    float z = abs(x);
    float t = 1.0 / (1.0 + 0.5 * z);
    float p = -0.82215223 + t * 0.17087277;
    p = 1.48851587 + t * p;
    p = -1.13520398 + t * p;
    p = 0.27886807 + t * p;
    p = -0.18628806 + t * p;
    p = 0.09678418 + t * p;
    p = 0.37409196 + t * p;
    p = 1.00002368 + t * p;
    float r = t * exp(-z * z - 1.26551223 + t * p);
    return x >= 0.0 ? r : 2.0 - r;
}

float rp_erf(float x) {
    return 1.0 - rp_erfc(x);
}

// The exact tier's Smith Lambda by its rational fit (float precision), as in the C++ float node.
const bool RP_LAMBDA_RATIONAL = true;
