#pragma once
/// GLSL 3.30 sources of the renderer (renderer.cpp). Colours are sRGB in and out; lighting
/// happens in linear space. Lights are fixed to the camera (view space, directions towards
/// the light): every view of a garment is lit alike, as in a photo studio.

namespace atelier::render::shaders {

inline constexpr const char* MESH_VERTEX = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec4 aColour;
layout(location = 3) in vec2 aUv;
layout(location = 4) in float aVisibility;
uniform mat4 uView;
uniform mat4 uProjection;
out vec3 vWorldNormal;
out vec3 vViewPosition;
out vec4 vColour;
out vec2 vUvMm;
out float vVisibility;
void main() {
    vec4 p = uView * vec4(aPosition, 1.0);
    vViewPosition = p.xyz;
    vWorldNormal = aNormal;
    vColour = aColour;
    vUvMm = 1000.0 * aUv;
    vVisibility = aVisibility;
    gl_Position = uProjection * p;
}
)";

/// The meshes' fragment shader, compiled in variants (renderer.cpp puts the `#define`s after
/// the version line): TRIANGLE_COLOURS (a colour per triangle from uTriangleColours), WEAVE (the
/// plain weave through the UVs), WIRE (the wireframe overlay's flat colour). Mesa's llvmpipe
/// pays for the texel fetch and the weave even where a uniform switches them off, so what a mesh
/// does not use is left out of its variant.
inline constexpr const char* MESH_FRAGMENT = R"(#version 330 core
#ifdef WIRE
uniform vec4 uWireColour;
out vec4 outColour;
void main() {
    outColour = uWireColour;
}
#else
in vec3 vWorldNormal;
in vec3 vViewPosition;
in vec4 vColour;
in vec2 vUvMm;
in float vVisibility;
uniform float uWeavePeriodMm;
uniform mat3 uViewRotation;
uniform samplerBuffer uTriangleColours;
uniform bool uGarment;
out vec4 outColour;

const vec3 KEY_DIR = vec3(-0.52, 0.62, 0.59);
const vec3 KEY = vec3(1.0, 0.96, 0.90) * 1.5;
const vec3 FILL_DIR = vec3(0.83, 0.17, 0.53);
const vec3 FILL = vec3(0.80, 0.87, 1.0) * 0.40;
const vec3 RIM_DIR = vec3(0.20, 0.50, -0.84);
const vec3 RIM = vec3(1.0) * 0.50;
const vec3 SKY = vec3(0.30, 0.32, 0.36);
const vec3 GROUND = vec3(0.14, 0.12, 0.11);

vec3 light(vec3 albedo, vec3 n, vec3 v, vec3 l, vec3 colour) {
    float cosine = dot(n, l);
    // Cloth scatters light a little past the terminator ("wrap" lighting); a body does not.
    float diffuse = uGarment ? max((cosine + 0.3) / 1.3, 0.0) : max(cosine, 0.0);
    float shininess = uGarment ? 12.0 : 40.0;
    float strength = uGarment ? 0.04 : 0.18;
    vec3 h = normalize(l + v);
    float specular = cosine > 0.0 ? strength * pow(max(dot(n, h), 0.0), shininess) : 0.0;
    return colour * (albedo * diffuse + vec3(specular));
}

#ifdef WEAVE
// A plain weave: threads one period apart, warp along v (the grain), weft along u, each
// passing over one thread and under the next. A thread is brightest along its middle; where it
// is on top it hides the crossing one. Where a thread is narrower than about two pixels the
// shade fades to its mean, so fine fabric reads as cloth, not moire. Scaled by the mean
// (0.8 + 0.2 * 2/pi) so that the fabric keeps its colour's brightness on average.
float weave(vec2 uvMm) {
    vec2 t = uvMm / uWeavePeriodMm;
    vec2 f = fract(t);
    bool warpOnTop = mod(floor(t.x) + floor(t.y), 2.0) < 1.0;
    float shade = (0.8 + 0.2 * (warpOnTop ? sin(3.14159265 * f.x) : sin(3.14159265 * f.y))) /
                  0.92732;
    vec2 w = fwidth(t);
    float detail = clamp(1.5 - 2.0 * max(w.x, w.y), 0.0, 1.0);
    return mix(1.0, shade, detail);
}
#endif

void main() {
#ifdef TRIANGLE_COLOURS
    vec4 base = texelFetch(uTriangleColours, gl_PrimitiveID);
#else
    vec4 base = vColour;
#endif
    vec3 albedo = pow(base.rgb, vec3(2.2));
#ifdef WEAVE
    albedo *= weave(vUvMm);
#endif
    vec3 nWorld = normalize(vWorldNormal);
    if (!gl_FrontFacing) {
        nWorld = -nWorld;
        if (uGarment) {
            // The back (inside) of the cloth: paler and darker than its front.
            albedo = mix(albedo, vec3(0.5), 0.5) * 0.35;
        }
    }
    vec3 n = normalize(uViewRotation * nWorld);
    vec3 v = normalize(-vViewPosition);
    vec3 colour = light(albedo, n, v, normalize(KEY_DIR), KEY);
    colour += light(albedo, n, v, normalize(FILL_DIR), FILL);
    colour += light(albedo, n, v, normalize(RIM_DIR), RIM);
    // Ambient occlusion: the sky's light fully, the lamps' by half (1 = none).
    colour = colour * (0.5 + 0.5 * vVisibility) +
             vVisibility * albedo * mix(GROUND, SKY, 0.5 + 0.5 * nWorld.y);
    if (uGarment) {
        colour += albedo * 0.3 * pow(1.0 - max(dot(n, v), 0.0), 3.0); // fabric sheen at grazing
    }
    // Highlights roll off softly above 0.8 instead of clipping; scaling the whole colour by
    // its largest component keeps the hue and saturation of brightly lit cloth.
    float peak = max(max(colour.r, colour.g), max(colour.b, 1e-6));
    if (peak > 0.8) {
        colour *= (0.8 + 0.2 * (1.0 - exp(-(peak - 0.8) / 0.2))) / peak;
    }
    outColour = vec4(pow(colour, vec3(1.0 / 2.2)), 1.0);
}
#endif
)";

inline constexpr const char* GROUND_VERTEX = R"(#version 330 core
layout(location = 0) in vec2 aCorner;
uniform mat4 uViewProjection;
uniform vec3 uCentre;
uniform vec2 uHalfSize;
out vec2 vLocal;
void main() {
    vLocal = aCorner;
    vec3 p = uCentre + vec3(aCorner.x * uHalfSize.x, 0.0, aCorner.y * uHalfSize.y);
    gl_Position = uViewProjection * vec4(p, 1.0);
}
)";

inline constexpr const char* GROUND_FRAGMENT = R"(#version 330 core
in vec2 vLocal;
uniform float uStrength;
out vec4 outColour;
void main() {
    float d = length(vLocal);
    outColour = vec4(0.0, 0.0, 0.0, uStrength * (1.0 - smoothstep(0.1, 1.0, d)));
}
)";

/// Lines over the meshes (seams): flat colour, each vertex moved `uTowardsCamera` metres towards
/// the eye along its view ray (the picture position stays; the depth wins against the surface
/// the line lies on).
inline constexpr const char* LINE_VERTEX = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
uniform mat4 uView;
uniform mat4 uProjection;
uniform float uTowardsCamera;
void main() {
    vec4 p = uView * vec4(aPosition, 1.0);
    float d = length(p.xyz);
    p.xyz *= max(d - uTowardsCamera, 0.5 * d) / max(d, 1e-9);
    gl_Position = uProjection * p;
}
)";

inline constexpr const char* LINE_FRAGMENT = R"(#version 330 core
uniform vec4 uColour;
out vec4 outColour;
void main() {
    outColour = uColour;
}
)";

} // namespace atelier::render::shaders
