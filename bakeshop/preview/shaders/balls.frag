// bakeshop preview: material balls in the baked sky, ray-traced per pixel (no meshes, so the
// numpy reference hits the same spheres at the same pixels).
//
// Each ball: uBalls[i] = (centre, radius); uBallMaterial[i] = (kind, roughness, albedo or F0, 0):
//   kind 0: Lambertian, albedo * sun DIM(n)      kind 1: Lambertian, albedo * shadow DIM(n)
//   kind 2: Lambertian, albedo * SH(n)           kind 3: GGX split-sum, F0 grey, + sun term
// uMode: 0 shaded colour; 1 (world normal, ball index + 1, 0 for the sky).

in vec2 vNdc;
out vec4 fragColor;

uniform mat4 uInvViewProj;
uniform int uMode;
uniform int uBallCount;
uniform vec4 uBalls[16];
uniform vec4 uBallMaterial[16];
uniform bool uSunLight;            // add the sun as a light to the GGX balls (sun.json)
uniform bool uDisplay;             // tone-map and encode here (the browser); else linear out

// the nearest ball the ray meets: index, or -1; t its distance along the ray
int nearestBall(vec3 o, vec3 d, out float tHit) {
    int hit = -1;
    tHit = 1e30;
    for (int i = 0; i < 16; ++i) {
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
    vec3 c;
    if (m.x < 0.5) c = m.z * dimAt(uSunDim, n);
    else if (m.x < 1.5) c = m.z * dimAt(uShadowDim, n);
    else if (m.x < 2.5) c = m.z * shAt(n);
    else {
        c = splitSum(n, -d, m.y, vec3(m.z));
        if (uSunLight) c += sunSpecular(n, -d, m.y, vec3(m.z));
    }
    fragColor = vec4(uDisplay ? display(c) : c, 1.0);
}
