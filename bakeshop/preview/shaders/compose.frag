// bakeshop preview: the golf course's last pass. Where the scene pass drew nothing, the sky;
// where the camera ray meets the water plane (y = 0) before the ground, the water, shaded with
// the reference water shader's own functions (bakeshop/water/shaders/water.frag, included
// before this file: ocean normals from the flipbook, ripples, the reflection lookup, the exact
// fresnel) over the ground the scene pass lit, seen through murk by the refracted path length.
//
// uReflection: 0 the fresnel-baked latlong (water.frag's uEnv: bakeshop.light.bake_fresnel, what
// an engine ships); 1 the HDR path: fresnel(n.v) times the baked cube at the mirror direction.
// uMode (water.frag's): 0 colour; 1 (water normal, 1 on water); 2 (path length, depth, 0, 1).

uniform sampler2D uSceneColor;     // the scene pass: linear colour
uniform sampler2D uScenePosition;  // world position, w = 1 where drawn
uniform bool uWater;
uniform int uReflection;
uniform bool uDisplay;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 ground = texelFetch(uScenePosition, px, 0);
    vec3 colour = texelFetch(uSceneColor, px, 0).rgb;
    vec3 o, d;
    cameraRay(uInvViewProj, vNdc, o, d);
    float tGround = ground.w > 0.5 ? dot(ground.xyz - o, d) : 1e30;
    float tWater = d.y < 0.0 && o.y > 0.0 ? -o.y / d.y : 1e30;
    bool water = uWater && tWater < tGround;
    if (!water && ground.w < 0.5) colour = skyAt(d);
    if (uMode != 0) {
        if (!water) { fragColor = vec4(0.0); return; }
    }
    if (water) {
        vec3 p = o + d * tWater;
        vec3 n = vec3(0.0, 1.0, 0.0);
        if (uNormalStrength > 0.0) {
            vec3 on = oceanNormal(p.xz);
            n = normalize(vec3(on.x * uNormalStrength, on.y, on.z * uNormalStrength));
        }
        if (uRippleStrength > 0.0) {
            vec4 rip = ripple(p.xz);
            vec2 slope = -n.xz / n.y + uRippleStrength * rip.x * rip.yz;
            n = normalize(vec3(-slope.x, 1.0, -slope.y));
        }
        vec3 v = -d;
        float f = fresnel(dot(v, n), uIor);
        vec3 r = reflect(d, n);
        if (r.y < 0.0) r.y = -r.y;     // a steep wave's mirror ray stays above the water
        vec3 reflection = uReflection == 0 ? envLookup(r) : f * skyAt(r);
        // under water: the ground this pixel sees, lit by the light left at its depth, seen
        // along the refracted ray (path = depth / cos) through beam attenuation and in-scatter
        float depth = ground.w > 0.5 ? max(-ground.y, 0.0) : uBottomDepth;
        vec3 t = refract(d, n, 1.0 / uIor);
        float path = depth / max(-t.y, 1e-3);
        vec3 sky = dimAt(uSunDim, vec3(0.0, 1.0, 0.0));
        vec3 bottom = ground.w > 0.5 ? colour : vec3(0.0);
        vec3 fog = uWaterInscatter * sky * (1.0 - exp(-uWaterC * path)) * exp(-uWaterKd * 0.5 * depth);
        vec3 below = bottom * exp(-uWaterKd * depth) * exp(-uWaterC * path) + fog;
        if (uMode == 1) { fragColor = vec4(n, 1.0); return; }
        if (uMode == 2) { fragColor = vec4(path, depth, 0.0, 1.0); return; }
        colour = reflection + (1.0 - f) * below;
    }
    fragColor = vec4(uDisplay ? display(colour) : colour, 1.0);
}
