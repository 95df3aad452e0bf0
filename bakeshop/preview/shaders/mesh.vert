// bakeshop preview: the golf course's meshes (terrain, boxes, tree billboards), world space in.
// uViewProj is the camera's for the colour pass and the sun's for the shadow pass.

in vec3 aPosition;
in vec3 aNormal;
in vec3 aAlbedo;
in vec2 aUv;
in vec3 aCentre;     // a tree's crown centre (its normals point away from it)
in float aKind;      // 0 opaque surface, 1 alpha-tested tree billboard

uniform mat4 uViewProj;

out vec3 vWorld;
out vec3 vNormal;
out vec3 vAlbedo;
out vec2 vUv;
out vec3 vCentre;
out float vKind;

void main() {
    vWorld = aPosition;
    vNormal = aNormal;
    vAlbedo = aAlbedo;
    vUv = aUv;
    vCentre = aCentre;
    vKind = aKind;
    gl_Position = uViewProj * vec4(aPosition, 1.0);
}
