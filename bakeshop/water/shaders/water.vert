#version 330
// bakeshop reference water shader: a full-screen triangle; the fragment shader casts one ray
// per pixel through uInvViewProj and shades where it meets the water plane y = 0.
out vec2 vNdc;
void main() {
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    vNdc = p * 2.0 - 1.0;
    gl_Position = vec4(vNdc, 0.0, 1.0);
}
