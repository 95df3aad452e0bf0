// bakeshop preview: the shading every pass shares, for both hosts (GLSL ES 3.00 in the browser,
// GLSL 3.30 through moderngl; bakeshop.preview.glsl adds the host's version and precision lines).
// World: right-handed, +Y up, -Z forward. Radiance in the bake's units. Each function says the
// equation bakeshop.preview.reference evaluates in numpy.

const float M_PI = 3.14159265358979;

uniform samplerCube uEnvCube;      // env_{face}: the environment as baked (OpenGL faces)
uniform samplerCube uSpecular;     // the GGX chain: level m holds roughness m / (levels - 1)
uniform float uSpecularLevels;     // levels in the chain
uniform sampler2D uSunDim;         // sun DIM, E/pi, latlong (row 0 = +Y)
uniform sampler2D uShadowDim;      // shadow DIM, the probe without its sun
uniform sampler2D uDfg;            // split-sum DFG: (scale, bias) on F0; columns n.v, rows r
uniform vec3 uSh[9];               // DIM (E/pi) SH coefficients as sh.json exports them
uniform vec3 uSunDirection;        // towards the sun (unit); (0, 0, 0) when there is none
uniform vec3 uSunIrradiance;       // E at normal incidence (sun.json irradiance)
uniform float uSunRadius;          // angular radius, radians
uniform float uSkyLevel;           // < 0: the environment cube; else this level of the chain

// display: exposure (stops), operator 0 none (clamp), 1 Reinhard, 2 ACES (Hill's fit); the same
// steps as bakeshop.image.to_picture, then sRGB encoding (the canvas quantises to 8 bits)
uniform float uExposure;
uniform int uOperator;

// bakeshop's latlong: u = atan(x, -z) / 2 pi + 1/2, v = acos(y) / pi (row 0 at the top, +Y);
// straight up or down (x = z = 0, where atan is undefined: a box's top face) u = 1/2
vec2 latlongUv(vec3 d) {
    float u = d.x == 0.0 && d.z == 0.0 ? 0.5 : atan(d.x, -d.z) / (2.0 * M_PI) + 0.5;
    return vec2(u, acos(clamp(d.y, -1.0, 1.0)) / M_PI);
}

// a DIM's value for the unit normal n: bilinear, u wrapping, v clamped at the poles
vec3 dimAt(sampler2D dim, vec3 n) {
    return textureLod(dim, latlongUv(n), 0.0).rgb;
}

// E(n)/pi from the 9 SH coefficients (real orthonormal, index l(l+1)+m; Y(1,-1) ~ y,
// Y(1,0) ~ z, Y(1,1) ~ x): bakeshop.light.sh.evaluate
vec3 shAt(vec3 n) {
    float x = n.x, y = n.y, z = n.z;
    return uSh[0] * 0.28209479177387814
         + uSh[1] * (0.4886025119029199 * y)
         + uSh[2] * (0.4886025119029199 * z)
         + uSh[3] * (0.4886025119029199 * x)
         + uSh[4] * (1.0925484305920792 * x * y)
         + uSh[5] * (1.0925484305920792 * y * z)
         + uSh[6] * (0.31539156525252005 * (3.0 * z * z - 1.0))
         + uSh[7] * (1.0925484305920792 * x * z)
         + uSh[8] * (0.5462742152960396 * (x * x - y * y));
}

// the sky seen along d: the baked cube, or one level of the specular chain
vec3 skyAt(vec3 d) {
    if (uSkyLevel < 0.0) return textureLod(uEnvCube, d, 0.0).rgb;
    return textureLod(uSpecular, d, uSkyLevel).rgb;
}

// split-sum GGX (Karis 2013): prefiltered(r, lod = roughness (levels - 1)) * (F0 A + B),
// (A, B) = DFG(n.v, roughness), r the mirror direction of the view
vec3 splitSum(vec3 n, vec3 v, float roughness, vec3 f0) {
    float nv = clamp(dot(n, v), 0.0, 1.0);
    vec3 r = reflect(-v, n);
    vec3 pre = textureLod(uSpecular, r, roughness * (uSpecularLevels - 1.0)).rgb;
    vec2 ab = textureLod(uDfg, vec2(nv, roughness), 0.0).rg;
    return pre * (f0 * ab.x + ab.y);
}

// the sun as a light: GGX D, height-correlated Smith visibility, Schlick's F, times n.l and
// sun.json's irradiance; alpha widened to at least the sun's angular radius (a mirror would
// otherwise see a delta)
vec3 sunSpecular(vec3 n, vec3 v, float roughness, vec3 f0) {
    vec3 l = uSunDirection;
    float nl = dot(n, l);
    float nv = max(dot(n, v), 1e-4);
    if (nl <= 0.0 || dot(l, l) == 0.0) return vec3(0.0);
    float a = max(roughness * roughness, uSunRadius);
    float a2 = a * a;
    vec3 h = normalize(l + v);
    float nh = max(dot(n, h), 0.0);
    float t = nh * nh * (a2 - 1.0) + 1.0;
    float d = a2 / (M_PI * t * t);
    float gv = nl * sqrt(nv * nv * (1.0 - a2) + a2);
    float gl = nv * sqrt(nl * nl * (1.0 - a2) + a2);
    float vis = 0.5 / (gv + gl);
    vec3 f = f0 + (1.0 - f0) * pow(1.0 - max(dot(v, h), 0.0), 5.0);
    return d * vis * f * nl * uSunIrradiance;
}

// the camera ray of a fragment: from the near plane through the far plane (clip -> world)
void cameraRay(mat4 invViewProj, vec2 ndc, out vec3 origin, out vec3 dir) {
    vec4 near = invViewProj * vec4(ndc, -1.0, 1.0);
    vec4 far = invViewProj * vec4(ndc, 1.0, 1.0);
    origin = near.xyz / near.w;
    dir = normalize(far.xyz / far.w - origin);
}

// an alpha-tested tree billboard: trunk and a lobed crown in the quad's (u, v), v up
bool treeCovers(vec2 uv) {
    if (abs(uv.x - 0.5) < 0.05 && uv.y < 0.4) return true;
    vec2 q = (uv - vec2(0.5, 0.64)) / vec2(0.42, 0.34);
    float lobes = 1.0 + 0.1 * sin(7.0 * atan(q.y, q.x));
    return dot(q, q) < lobes * lobes;
}

float srgbEncode(float x) {
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

// bakeshop.image.to_picture's steps: exposure, operator, clamp, sRGB
vec3 display(vec3 c) {
    c *= exp2(uExposure);
    if (uOperator == 1) {
        float lum = max(dot(c, vec3(0.2126, 0.7152, 0.0722)), 0.0);
        c *= 1.0 / (1.0 + lum);
    } else if (uOperator == 2) {
        vec3 x = vec3(dot(vec3(0.59719, 0.35458, 0.04823), c),
                      dot(vec3(0.07600, 0.90834, 0.01566), c),
                      dot(vec3(0.02840, 0.13383, 0.83777), c));
        vec3 y = (x * (x + 0.0245786) - 0.000090537) / (x * (0.983729 * x + 0.4329510) + 0.238081);
        c = vec3(dot(vec3(1.60475, -0.53108, -0.07367), y),
                 dot(vec3(-0.10208, 1.10813, -0.00605), y),
                 dot(vec3(-0.00327, -0.07276, 1.07602), y));
    }
    c = clamp(c, 0.0, 1.0);
    return vec3(srgbEncode(c.r), srgbEncode(c.g), srgbEncode(c.b));
}
