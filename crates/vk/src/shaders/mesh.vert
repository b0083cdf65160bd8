#version 450
// Triangle pass: world-space positions, normals, one scalar and one colour per vertex (the
// colour stream is read by the colour shading only).

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in float a_scalar;
layout(location = 3) in vec3 a_color;

layout(push_constant) uniform Push {
    mat4 view_proj;
    vec4 eye;     // xyz: eye position (world)
    vec4 forward; // xyz: unit viewing direction (world)
    vec4 light;   // xyz: unit direction towards the key light (world)
    vec4 params;  // x: scalar minimum, y: 1 / scalar range, z: shading mode (4: colours)
} pc;

layout(location = 0) out vec3 v_normal;
layout(location = 1) out vec3 v_world;
layout(location = 2) out float v_scalar;
layout(location = 3) flat out float v_scalar_flat;
layout(location = 4) out vec3 v_color;

void main() {
    v_normal = a_normal;
    v_world = a_position;
    v_scalar = a_scalar;
    v_scalar_flat = a_scalar;
    v_color = pc.params.z > 3.5 ? a_color : vec3(0.0);
    gl_Position = pc.view_proj * vec4(a_position, 1.0);
}
