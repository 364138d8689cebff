// Which film pixel a wave's j-th pixel is: pixel pixel_begin + j, or with adaptive sampling (`--adaptive`,
// SPEC_PIXEL_LIST) the pixel list's entry pixel_begin + j (render/adaptive_render.h orders the film's pixels so that
// those given the most samples come first, and a wave takes a prefix of the list). Adaptive sampling also counts the
// work each path takes (path_work: generate zeroes it, shade adds PATH_WORK_HIT or _ESCAPE per vertex and
// PATH_WORK_SHADOW_RAY per shadow ray, accumulate sums it into pixel_work), so that the pilot can weigh each pixel's
// cost per sample.
// Without `--adaptive` all of it is compiled out. GLSL only.
#ifndef FH_WAVE_PIXELS_GLSL
#define FH_WAVE_PIXELS_GLSL

layout(constant_id = SPEC_PIXEL_LIST) const bool pixel_list_on = false;

uint wave_film_pixel(uint j) {
    uint entry = push.pixel_begin + j;
    return pixel_list_on ? pixel_list[entry] : entry;
}

#endif
