// bakeshop preview: the golf course, lit by the DIM pair through a shadow map from sun.json's
// direction. A fragment the sun reaches takes the sun DIM, a shadowed one the shadow DIM (the
// probe without its sun): the two lookups at the same normal differ by the sun's share.
//
// uDiffuse: 0 the pair by the shadow map; 1 the sun DIM everywhere; 2 the shadow DIM everywhere;
// 3 the SH irradiance (sh.json) everywhere.
// uMode: 0 shaded colour; 1 (normal, lit 0/1); 2 (albedo, lit 0/1).
// Outputs: colour (linear), and the world position with 1 in w (0 where nothing was drawn).

in vec3 vWorld;
in vec3 vNormal;
in vec3 vAlbedo;
in vec2 vUv;
in vec3 vCentre;
in float vKind;

layout(location = 0) out vec4 fragColor;
layout(location = 1) out vec4 fragPosition;

uniform int uMode;
uniform int uDiffuse;
uniform sampler2D uShadowMap;      // depth from the sun, [0, 1]
uniform mat4 uShadowViewProj;      // world -> the sun's clip space (orthographic)
uniform float uShadowOffset;       // metres along the normal before the lookup (no acne)
uniform bool uHasShadows;          // false when the probe has no sun (all fragments lit)

// 1 where the shadow map sees this point first (the sun reaches it), 0 where something nearer
// the sun covers it: one nearest texel, so both hosts and the reference agree exactly
float sunVisibility(vec3 p, vec3 n) {
    if (!uHasShadows) return 1.0;
    if (dot(n, uSunDirection) <= 0.0) return 0.0;     // facing away: its own shadow
    vec4 c = uShadowViewProj * vec4(p + n * uShadowOffset, 1.0);
    vec3 s = c.xyz / c.w * 0.5 + 0.5;
    if (any(lessThan(s.xy, vec2(0.0))) || any(greaterThan(s.xy, vec2(1.0)))) return 1.0;
    float nearest = texture(uShadowMap, s.xy).r;
    return s.z <= nearest ? 1.0 : 0.0;
}

void main() {
    vec3 n;
    if (vKind > 0.5) {
        if (!treeCovers(vUv)) discard;
        // the crown shades as a ball round its centre, the trunk as a vertical cylinder
        // (the quad's own normal breaks the tie on its centre line)
        vec3 away = vWorld - vCentre;
        if (vUv.y < 0.4 && abs(vUv.x - 0.5) < 0.05) away.y = 0.0;
        n = normalize(away + 0.01 * vNormal);
    } else {
        n = normalize(vNormal);
    }
    float lit = sunVisibility(vWorld, n);
    vec3 e;
    if (uDiffuse == 1) e = dimAt(uSunDim, n);
    else if (uDiffuse == 2) e = dimAt(uShadowDim, n);
    else if (uDiffuse == 3) e = shAt(n);
    else e = lit > 0.5 ? dimAt(uSunDim, n) : dimAt(uShadowDim, n);
    fragPosition = vec4(vWorld, 1.0);
    if (uMode == 1) fragColor = vec4(n, lit);
    else if (uMode == 2) fragColor = vec4(vAlbedo, lit);
    else fragColor = vec4(vAlbedo * e, 1.0);
}
