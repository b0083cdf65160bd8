#version 450
// Overlay pass (HUD, legends): rectangles in pixels (origin top-left, y down), colour per vertex.

layout(location = 0) in vec3 a_position; // xy: pixels
layout(location = 1) in vec3 a_color;
layout(location = 2) in float a_alpha;

layout(push_constant) uniform Push {
    mat4 unused;
    vec4 params; // xy: 2 / target size in pixels
} pc;

layout(location = 0) out vec4 v_color;

void main() {
    v_color = vec4(a_color, a_alpha);
    // Vulkan NDC: y points down, as pixel rows do.
    gl_Position = vec4(a_position.xy * pc.params.xy - 1.0, 0.0, 1.0);
}
