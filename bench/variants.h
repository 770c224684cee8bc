// variants.h: generated C++ variants of the core (cpp/<variant>.inc, written at build time by
// retroprism_glsl_gen --out from the same regions as the GLSL variants), each in a float
// namespace of its own: lobes and modes fixed at compile time, the code they leave out absent.
#pragma once

#include "prism_core.h"

#define RP_VARIANT_F32_PRELUDE                                                                     \
    using real = float;                                                                            \
    using vec2 = glm::vec2;                                                                        \
    using vec3 = glm::vec3;                                                                        \
    using vec4 = glm::vec4;                                                                        \
    RP_CORE_PRELUDE

// A variant that leaves a lobe out leaves some of the core's parameters and locals unused.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-variable"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"

namespace retroprism::variants {

namespace retro_f32 {
RP_VARIANT_F32_PRELUDE
#include "prism_special.inc"
RP_ERFINV_REFINED(1)
#include "generated/prism_tables.inc"
#include "cpp/prismatic_retroreflector_retro.inc"
} // namespace retro_f32

namespace retro_diffuse_f32 {
RP_VARIANT_F32_PRELUDE
#include "prism_special.inc"
RP_ERFINV_REFINED(1)
#include "generated/prism_tables.inc"
#include "cpp/prismatic_retroreflector_retro_diffuse.inc"
} // namespace retro_diffuse_f32

namespace averaged_ideal_f32 {
RP_VARIANT_F32_PRELUDE
#include "prism_special.inc"
RP_ERFINV_REFINED(1)
#include "generated/prism_tables.inc"
#include "cpp/prismatic_retroreflector_averaged_ideal.inc"
} // namespace averaged_ideal_f32

namespace averaged_ideal_fast_f32 {
RP_VARIANT_F32_PRELUDE
#include "prism_special.inc"
RP_ERFINV_REFINED(1)
#include "generated/prism_tables.inc"
#include "cpp/prismatic_retroreflector_averaged_ideal_fast.inc"
} // namespace averaged_ideal_fast_f32

namespace averaged_tir_f32 {
RP_VARIANT_F32_PRELUDE
#include "prism_special.inc"
RP_ERFINV_REFINED(1)
#include "generated/prism_tables.inc"
#include "cpp/prismatic_retroreflector_averaged_tir.inc"
} // namespace averaged_tir_f32

namespace averaged_tir_fast_f32 {
RP_VARIANT_F32_PRELUDE
#include "prism_special.inc"
RP_ERFINV_REFINED(1)
#include "generated/prism_tables.inc"
#include "cpp/prismatic_retroreflector_averaged_tir_fast.inc"
} // namespace averaged_tir_fast_f32

} // namespace retroprism::variants

#pragma GCC diagnostic pop

#undef RP_VARIANT_F32_PRELUDE
