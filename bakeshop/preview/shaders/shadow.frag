// bakeshop preview: the sun's shadow map (depth only); tree billboards cut by their alpha.

in vec3 vWorld;
in vec3 vNormal;
in vec3 vAlbedo;
in vec2 vUv;
in vec3 vCentre;
in float vKind;

void main() {
    if (vKind > 0.5 && !treeCovers(vUv)) discard;
}
