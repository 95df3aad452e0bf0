// bakeshop preview: material balls in the baked sky, ray-traced per pixel (no meshes, so the
// numpy reference hits the same spheres at the same pixels).
//
// Each ball: uBalls[i] = (centre, radius); uBallMaterial[i] = (kind, roughness, metalness, 0);
// uBallColor[i].rgb its albedo or base colour (linear):
//   kind 0: Lambertian, albedo * sun DIM(n)      kind 1: Lambertian, albedo * shadow DIM(n)
//   kind 2: Lambertian, albedo * SH(n)
//   kind 3: metallic-roughness GGX (the glTF / Filament material): diffuse
//           (1 - metalness) base * sun DIM(n), plus the split sum with F0 = mix(0.04, base,
//           metalness), plus sun.json's sun as a light when uSunLight
// uMode: 0 shaded colour; 1 (world normal, ball index + 1, 0 for the sky).

in vec2 vNdc;
out vec4 fragColor;

uniform mat4 uInvViewProj;
uniform int uMode;
uniform int uBallCount;
uniform vec4 uBalls[32];
uniform vec4 uBallMaterial[32];
uniform vec4 uBallColor[32];
uniform bool uSunLight;            // add the sun as a light to the GGX balls (sun.json)
uniform bool uDisplay;             // tone-map and encode here (the browser); else linear out

// the nearest ball the ray meets: index, or -1; t its distance along the ray
int nearestBall(vec3 o, vec3 d, out float tHit) {
    int hit = -1;
    tHit = 1e30;
    for (int i = 0; i < 32; ++i) {
        if (i >= uBallCount) break;
        vec3 oc = o - uBalls[i].xyz;
        float b = dot(oc, d);
        float c = dot(oc, oc) - uBalls[i].w * uBalls[i].w;
        float disc = b * b - c;
        if (disc < 0.0) continue;
        float t = -b - sqrt(disc);
        if (t > 0.0 && t < tHit) { tHit = t; hit = i; }
    }
    return hit;
}

void main() {
    vec3 o, d;
    cameraRay(uInvViewProj, vNdc, o, d);
    float t;
    int i = nearestBall(o, d, t);
    if (i < 0) {
        vec3 sky = skyAt(d);
        fragColor = uMode == 1 ? vec4(0.0) : vec4(uDisplay ? display(sky) : sky, 1.0);
        return;
    }
    vec3 n = normalize(o + d * t - uBalls[i].xyz);
    if (uMode == 1) { fragColor = vec4(n, float(i + 1)); return; }
    vec4 m = uBallMaterial[i];
    vec3 base = uBallColor[i].rgb;
    vec3 c;
    if (m.x < 0.5) c = base * dimAt(uSunDim, n);
    else if (m.x < 1.5) c = base * dimAt(uShadowDim, n);
    else if (m.x < 2.5) c = base * shAt(n);
    else {
        vec3 f0 = mix(vec3(0.04), base, m.z);
        c = (1.0 - m.z) * base * dimAt(uSunDim, n) + splitSum(n, -d, m.y, f0);
        if (uSunLight) c += sunSpecular(n, -d, m.y, f0);
    }
    fragColor = vec4(uDisplay ? display(c) : c, 1.0);
}
