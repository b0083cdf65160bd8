#version 450
// Triangle pass: grey headlight/key-light shading, discrete depth palette or
// heat map; also writes the auxiliary normal + scalar and linear depth targets
// (not with COLOR_ONLY: the multisampled pass has the colour target only).
//
// Normal and scalar are interpolated at the centroid of the covered samples
// (`smooth centroid`: naga drops a bare `centroid`): with several samples per
// pixel a triangle that covers some of them but not the pixel's centre is shaded
// at a point inside it, never with values extrapolated beyond its corners. A
// sub-pixel strip beside a crease, whose corners carry one-sided normals, would
// otherwise take a normal far outside its corners' and show as a dot. With one
// sample the centroid is the pixel's centre.

layout(push_constant) uniform Push {
    mat4 view_proj;
    vec4 eye;
    vec4 forward;
    vec4 light;
    vec4 params;
} pc;

layout(location = 0) smooth centroid in vec3 v_normal;
layout(location = 1) in vec3 v_world;
layout(location = 2) smooth centroid in float v_scalar;
layout(location = 3) flat in float v_scalar_flat;
layout(location = 4) smooth centroid in vec3 v_color;

layout(location = 0) out vec4 o_color;
#ifndef COLOR_ONLY
layout(location = 1) out vec4 o_normal_scalar;
layout(location = 2) out vec4 o_linear_depth;
#endif

// Per-level colours for subdivision depth 0, 1, 2, ... (cycled after 8).
vec3 depth_colour(int level) {
    int i = level % 8;
    if (i == 0) { return vec3(0.20, 0.35, 0.90); }
    if (i == 1) { return vec3(0.10, 0.75, 0.85); }
    if (i == 2) { return vec3(0.20, 0.80, 0.25); }
    if (i == 3) { return vec3(0.95, 0.90, 0.15); }
    if (i == 4) { return vec3(1.00, 0.55, 0.10); }
    if (i == 5) { return vec3(0.90, 0.15, 0.15); }
    if (i == 6) { return vec3(0.85, 0.25, 0.80); }
    return vec3(0.55, 0.30, 0.75);
}

// Blue -> cyan -> green -> yellow -> red.
vec3 heat_colour(float t) {
    float r = clamp(1.5 - abs(4.0 * t - 3.0), 0.0, 1.0);
    float g = clamp(1.5 - abs(4.0 * t - 2.0), 0.0, 1.0);
    float b = clamp(1.5 - abs(4.0 * t - 1.0), 0.0, 1.0);
    return vec3(r, g, b);
}

void main() {
    vec3 n = v_normal;
    float len = length(n);
    if (len > 0.0) {
        n = n / len;
    } else {
        n = vec3(0.0, 0.0, 0.0);
    }
    vec3 to_eye = normalize(pc.eye.xyz - v_world);
    vec3 ns = n;
    if (dot(ns, to_eye) < 0.0) {
        ns = -ns; // two-sided lighting
    }
    float key = max(dot(ns, pc.light.xyz), 0.0);
    float head = max(dot(ns, to_eye), 0.0);
    float lit = 0.12 + 0.55 * key + 0.33 * head;

    int mode = int(pc.params.z + 0.5);
    vec3 base = vec3(0.80, 0.80, 0.80);
    if (mode == 2) {
        int level = int(floor(max(v_scalar_flat, 0.0) + 0.5));
        base = depth_colour(level);
    } else if (mode == 3) {
        float t = clamp((v_scalar - pc.params.x) * pc.params.y, 0.0, 1.0);
        base = heat_colour(t);
    } else if (mode == 4) {
        base = clamp(v_color, vec3(0.0), vec3(1.0));
    }
    o_color = vec4(clamp(base * lit, vec3(0.0), vec3(1.0)), 1.0);
#ifndef COLOR_ONLY
    o_normal_scalar = vec4(n, v_scalar);
    o_linear_depth = vec4(dot(v_world - pc.eye.xyz, pc.forward.xyz), 0.0, 0.0, 0.0);
#endif
}
