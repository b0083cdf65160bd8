#version 450
// Line pass: wireframe edges and extra polylines, flat colour.

layout(location = 0) in vec3 a_position;

layout(push_constant) uniform Push {
    mat4 view_proj;
    vec4 color;
} pc;

void main() {
    gl_Position = pc.view_proj * vec4(a_position, 1.0);
}
