#version 330
// bakeshop reference water shader (SI units: metres, seconds).
//
// Reads what `bakeshop water` writes: the looping ocean normal flipbook as a texture array
// (packed (n + 1) / 2, tangent frame x = world +X, y = world -Z, z = world +Y; two-channel maps
// rebuild z), the fresnel-baked latlong environment (`bakeshop fresnel`), the murk constants
// (`bakeshop water murk`) and the rain atlas with the ring lookup table
// (`bakeshop water ripples`). World: +Y up, -Z forward; the water plane is y = 0.
//
// uMode selects the output: 0 shaded colour; 1 world normal; 2 (underwater path length,
// bottom hit x, bottom hit z); 3 (ripple slope d eta / dr, ripple mask, ripple radius).

in vec2 vNdc;
out vec4 fragColor;

uniform mat4 uInvViewProj;     // clip space -> world; rays run from the near to the far plane
uniform int uMode;

uniform sampler2DArray uNormals;
uniform bool uNormalXY;         // two-channel (BC5-ready) maps: rebuild z
uniform int uFrames;            // layers in the array: frames per loop
uniform float uFrameRate;       // frames per second (frames / loop period)
uniform float uTime;            // seconds
uniform float uTileSize;        // metres per tile
uniform float uNormalStrength;  // 0: flat water

uniform sampler2D uEnv;         // fresnel-baked latlong environment (linear)
uniform float uIor;

uniform float uBottomDepth;     // metres below the surface
uniform vec3 uWaterC;           // beam attenuation per channel, 1/m
uniform vec3 uWaterKd;          // diffuse attenuation per channel, 1/m
uniform vec3 uWaterInscatter;   // in-scatter at infinity near the surface (per E(0)/pi)

uniform sampler2D uRain;        // rain atlas: RG offset to the drop in cells, B phase, A mask
uniform sampler2D uRing;        // ring LUT: rows time 0..duration, columns radius 0..radius
uniform float uRainCell;        // metres per rain cell
uniform float uRainTile;        // metres per rain atlas tile
uniform float uRingRadius;      // metres covered by the LUT's columns
uniform float uRingDuration;    // seconds covered by the LUT's rows
uniform float uRippleStrength;  // 0: no ripples

const float PI = 3.14159265358979;

// texel centres: s = x / tile, t = z / tile (row 0, the picture's top, is tangent y = size)
vec3 oceanNormal(vec2 xz) {
    vec2 st = xz / uTileSize;
    float f = uTime * uFrameRate;
    float f0 = floor(f);
    float w = f - f0;
    float a = mod(f0, float(uFrames));
    float b = mod(f0 + 1.0, float(uFrames));
    vec3 c0 = texture(uNormals, vec3(st, a)).rgb;
    vec3 c1 = texture(uNormals, vec3(st, b)).rgb;
    vec3 c = mix(c0, c1, w);
    vec3 n = c * 2.0 - 1.0;
    if (uNormalXY) n.z = sqrt(max(0.0, 1.0 - dot(n.xy, n.xy)));
    n = normalize(n);
    // tangent (x along u = +X, y along v up = -Z, z out = +Y) -> world
    return vec3(n.x, n.z, -n.y);
}

// ripple slope (d eta / dr) at xz, the drop's outward direction in world xz, and its mask
vec4 ripple(vec2 xz) {
    vec2 st = xz / uRainTile;
    vec4 drop = texture(uRain, st);
    vec2 d = drop.rg * 2.0 - 1.0;              // (texel - centre) in cells, tangent x, y
    float r = length(d) * uRainCell;
    float tau = fract(uTime / uRingDuration + drop.b);
    float slope = texture(uRing, vec2(r / uRingRadius, tau)).g * drop.a;
    vec2 dir = r > 0.0 ? normalize(vec2(d.x, -d.y)) : vec2(0.0);  // tangent -> world xz
    return vec4(slope, dir, drop.a);
}

vec3 envLookup(vec3 d) {
    // bakeshop latlong: phi = atan(x, -z), u = phi / 2 pi + 1/2, v = acos(y) / pi
    float u = atan(d.x, -d.z) / (2.0 * PI) + 0.5;
    float v = acos(clamp(d.y, -1.0, 1.0)) / PI;
    return texture(uEnv, vec2(u, v)).rgb;
}

float fresnel(float c, float n) {
    // exact unpolarised reflectance (bakeshop.light.fresnel.fresnel_dielectric)
    c = clamp(c, 0.0, 1.0);
    float g2 = n * n - 1.0 + c * c;
    if (g2 < 0.0) return 1.0;
    float g = sqrt(g2);
    float a = (g - c) / (g + c);
    float b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    return 0.5 * a * a * (1.0 + b * b);
}

vec3 checker(vec2 xz) {
    vec2 q = floor(xz);
    return mod(q.x + q.y, 2.0) < 1.0 ? vec3(0.8, 0.75, 0.6) : vec3(0.35, 0.3, 0.25);
}

void main() {
    vec4 near = uInvViewProj * vec4(vNdc, -1.0, 1.0);
    vec4 far = uInvViewProj * vec4(vNdc, 1.0, 1.0);
    vec3 origin = near.xyz / near.w;
    vec3 dir = normalize(far.xyz / far.w - origin);
    if (dir.y >= 0.0 || origin.y <= 0.0) {
        fragColor = vec4(uMode == 0 ? envLookup(dir) : vec3(0.0), 1.0);
        return;
    }
    vec3 p = origin + dir * (-origin.y / dir.y);   // on the water plane
    vec3 n = vec3(0.0, 1.0, 0.0);
    if (uNormalStrength > 0.0) {
        vec3 o = oceanNormal(p.xz);
        n = normalize(vec3(o.x * uNormalStrength, o.y, o.z * uNormalStrength));
    }
    vec4 rip = vec4(0.0);
    if (uRippleStrength > 0.0) {
        rip = ripple(p.xz);
        // add the ripple's slope to the surface's: n ~ (-dh/dx, 1, -dh/dz)
        vec2 slope = -n.xz / n.y + uRippleStrength * rip.x * rip.yz;
        n = normalize(vec3(-slope.x, 1.0, -slope.y));
    }
    if (uMode == 1) { fragColor = vec4(n, 1.0); return; }
    if (uMode == 3) { fragColor = vec4(rip.x, rip.w, 0.0, 1.0); return; }

    vec3 v = -dir;
    float cosv = dot(v, n);
    vec3 reflection = envLookup(reflect(dir, n));       // fresnel already baked in
    vec3 t = refract(dir, n, 1.0 / uIor);
    vec3 below = vec3(0.0);
    float path = 0.0;
    vec3 hit = vec3(0.0);
    if (dot(t, t) > 0.0 && t.y < 0.0) {
        path = (-uBottomDepth - p.y) / t.y;
        hit = p + t * path;
        vec3 light = exp(-uWaterKd * uBottomDepth);          // ambient light at the bottom
        vec3 fog = uWaterInscatter * (1.0 - exp(-uWaterC * path))
                   * exp(-uWaterKd * 0.5 * uBottomDepth);   // mean depth of the path
        below = checker(hit.xz) * light * exp(-uWaterC * path) + fog;
    }
    if (uMode == 2) { fragColor = vec4(path, hit.x, hit.z, 1.0); return; }
    fragColor = vec4(reflection + (1.0 - fresnel(cosv, uIor)) * below, 1.0);
}
