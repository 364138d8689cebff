// Which robustness techniques are on (layout.h TECHNIQUE_*). All are on unless `--disable-technique` turns
// one off to measure what it costs and what goes wrong without it; in the stages the switch is a
// specialization constant, so the branches it guards are resolved when the pipeline is compiled. Compiled
// as C++ (tests), every technique is on.
#ifndef FH_TECHNIQUES_GLSL
#define FH_TECHNIQUES_GLSL
#ifdef __cplusplus
#define FH_TECHNIQUE_ON(technique) true
#else
#include "shared/layout.h"
layout(constant_id = SPEC_DISABLED_TECHNIQUES) const uint disabled_techniques = 0u;
#define FH_TECHNIQUE_ON(technique) ((disabled_techniques & (technique)) == 0u)
#endif
#endif
