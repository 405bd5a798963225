// Screen-space directional occlusion and SSAO as render passes: the GPU twin of vcut-ssdo
// (crates/vcut-ssdo/src/ssdo.rs), formula for formula. Passes: G-buffer (two layers), sun
// shadow map, sampling, indirect bounce, separable geometry-aware blur (two passes), composite.
//
// Every colour texture is Rgba32Uint holding 32-bit floats as their bits (`ld` reads them,
// `st` writes them): exact like Rgba32Float, and renderable on every adapter — OpenGL (llvmpipe
// included) cannot render to Rgba32Float.

struct Uniforms {
    view_proj: mat4x4<f32>,
    shadow_view: mat4x4<f32>,
    eye: vec4<f32>,
    // xyz: toward the sun; w: 1 when there is a sun.
    sun_dir: vec4<f32>,
    sun_irradiance: vec4<f32>,
    // width, height, shadow-map size, shadow-map half extent
    size: vec4<f32>,
    // r_max, depth limit, bleed, shadow bias
    p0: vec4<f32>,
    // samples N, sets M, peel, method (0 SSAO, 1 SSDO)
    p1: vec4<u32>,
    // indirect, blur radius, cone table size, irradiance table size
    p2: vec4<u32>,
    // shadow depth scale (depth / scale in [0, 1]), blur direction x, y, unused
    p3: vec4<f32>,
};

@group(0) @binding(0) var<uniform> u: Uniforms;

const PI: f32 = 3.14159265358979;

// A packed texel as the floats it holds.
fn ld(t: texture_2d<u32>, q: vec2<i32>) -> vec4<f32> {
    return bitcast<vec4<f32>>(textureLoad(t, q, 0));
}

// Floats as a packed texel.
fn st(v: vec4<f32>) -> vec4<u32> {
    return bitcast<vec4<u32>>(v);
}

// ---- geometry: G-buffer layers and the shadow map ----

struct GOut {
    @builtin(position) pos: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) object: u32,
    @location(3) w: f32,
};

@vertex
fn vs_gbuffer(@location(0) p: vec3<f32>, @location(1) n: vec3<f32>, @location(2) object: f32) -> GOut {
    var out: GOut;
    let c = u.view_proj * vec4<f32>(p, 1.0);
    out.pos = c;
    out.world = p;
    out.normal = n;
    out.object = u32(object);
    out.w = c.w;
    return out;
}

// 32 bytes per pixel (the downlevel limit): albedo comes from the object's entry in `albedos`.
struct GTargets {
    @location(0) position: vec4<u32>,
    // xyz: the normal facing the camera; w: object index + 1.
    @location(1) normal: vec4<u32>,
};

fn gbuffer_targets(in: GOut) -> GTargets {
    var n = normalize(in.normal);
    if (dot(n, u.eye.xyz - in.world) < 0.0) {
        n = -n;
    }
    var out: GTargets;
    out.position = st(vec4<f32>(in.world, in.w));
    out.normal = st(vec4<f32>(n, f32(in.object + 1u)));
    return out;
}

@fragment
fn fs_gbuffer(in: GOut) -> GTargets {
    return gbuffer_targets(in);
}

// The second layer: the nearest surface clearly behind the first (g_position, bound below).
@fragment
fn fs_gbuffer_second(in: GOut) -> GTargets {
    let f = ld(g_position, vec2<i32>(in.pos.xy));
    if (f.w > 0.0 && in.w <= f.w * (1.0 + 1e-4)) {
        discard;
    }
    return gbuffer_targets(in);
}

@vertex
fn vs_shadow(@location(0) p: vec3<f32>, @location(1) n: vec3<f32>, @location(2) object: f32) -> @builtin(position) vec4<f32> {
    let v = u.shadow_view * vec4<f32>(p, 1.0);
    return vec4<f32>(v.x / u.size.w, v.y / u.size.w, -v.z / u.p3.x, 1.0);
}

// The shadow map's depths as f32 bits in an R32Uint target (cleared to the bits of 1.0, as a
// depth buffer): OpenGL shaders cannot `textureLoad` a depth texture.
@fragment
fn fs_shadow(@builtin(position) pos: vec4<f32>) -> @location(0) u32 {
    return bitcast<u32>(pos.z);
}

// ---- full-screen passes ----

@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let x = f32((i << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(i & 2u) * 2.0 - 1.0;
    return vec4<f32>(x, y, 0.0, 1.0);
}

@group(1) @binding(0) var g_position: texture_2d<u32>;
@group(1) @binding(1) var g_normal: texture_2d<u32>;
@group(1) @binding(2) var<storage, read> albedos: array<vec4<f32>>;
@group(1) @binding(3) var g_second: texture_2d<u32>;
@group(1) @binding(4) var<storage, read> samples: array<vec4<f32>>;

// Pass-specific inputs.
@group(2) @binding(0) var in_a: texture_2d<u32>;
@group(2) @binding(1) var in_b: texture_2d<u32>;
@group(2) @binding(2) var in_c: texture_2d<u32>;
@group(2) @binding(3) var shadow_map: texture_2d<u32>;

fn albedo_at(q: vec2<i32>) -> vec3<f32> {
    return albedos[u32(ld(g_normal, q).w) - 1u].xyz;
}

fn basis(n: vec3<f32>) -> mat2x3<f32> {
    var sgn = 1.0;
    if (n.z < 0.0) {
        sgn = -1.0;
    }
    let a = -1.0 / (sgn + n.z);
    let b = n.x * n.y * a;
    return mat2x3<f32>(
        vec3<f32>(1.0 + sgn * n.x * n.x * a, sgn * b, -sgn * n.x),
        vec3<f32>(b, sgn + n.y * n.y * a, -n.y),
    );
}

// The pixel sample point s projects to (s known to be in front of the camera and on screen:
// an occluded sample's).
fn pixel_of(s: vec3<f32>) -> vec2<i32> {
    let c = u.view_proj * vec4<f32>(s, 1.0);
    let x = (c.x / c.w * 0.5 + 0.5) * u.size.x;
    let y = (0.5 - c.y / c.w * 0.5) * u.size.y;
    return vec2<i32>(i32(x), i32(y));
}

// The pixel whose stored surface occludes sample point s, or (-1, -1).
fn occluder(s: vec3<f32>) -> vec2<i32> {
    let none = vec2<i32>(-1, -1);
    let c = u.view_proj * vec4<f32>(s, 1.0);
    if (c.w <= 0.01) {
        return none;
    }
    let x = (c.x / c.w * 0.5 + 0.5) * u.size.x;
    let y = (0.5 - c.y / c.w * 0.5) * u.size.y;
    if (x < 0.0 || y < 0.0 || x >= u.size.x || y >= u.size.y) {
        return none;
    }
    let q = vec2<i32>(i32(x), i32(y));
    let front = ld(g_position, q);
    if (front.w <= 0.0) {
        return none;
    }
    let n = ld(g_normal, q).xyz;
    if (dot(s - front.xyz, n) >= -0.02 * u.p0.x || front.w >= c.w) {
        return none;
    }
    if (u.p1.z == 1u) {
        let back = ld(g_second, q);
        if (back.w > 0.0 && c.w >= back.w) {
            return none;
        }
        return q;
    }
    if (c.w - front.w > u.p0.y) {
        return none;
    }
    return q;
}

fn oct_encode(d: vec3<f32>) -> vec2<f32> {
    let a = d / max(abs(d.x) + abs(d.y) + abs(d.z), 1e-30);
    if (a.z >= 0.0) {
        return a.xy;
    }
    return vec2<f32>((1.0 - abs(a.y)) * select(-1.0, 1.0, a.x >= 0.0), (1.0 - abs(a.x)) * select(-1.0, 1.0, a.y >= 0.0));
}

// Bilinear octahedral lookup (vcut_ssdo::light::Octahedral::get).
fn oct_get(t: texture_2d<u32>, size: u32, d: vec3<f32>) -> vec3<f32> {
    let uv = oct_encode(d);
    let n = f32(size);
    let x = clamp((uv.x * 0.5 + 0.5) * n - 0.5, 0.0, n - 1.0);
    let y = clamp((uv.y * 0.5 + 0.5) * n - 0.5, 0.0, n - 1.0);
    let x0 = i32(floor(x));
    let y0 = i32(floor(y));
    let x1 = min(x0 + 1, i32(size) - 1);
    let y1 = min(y0 + 1, i32(size) - 1);
    let fx = x - f32(x0);
    let fy = y - f32(y0);
    let a = ld(t, vec2<i32>(x0, y0)).xyz * (1.0 - fx) + ld(t, vec2<i32>(x1, y0)).xyz * fx;
    let b = ld(t, vec2<i32>(x0, y1)).xyz * (1.0 - fx) + ld(t, vec2<i32>(x1, y1)).xyz * fx;
    return a * (1.0 - fy) + b * fy;
}

fn sun_lit(p: vec3<f32>) -> f32 {
    let v = u.shadow_view * vec4<f32>(p, 1.0);
    let size = u.size.z;
    let x = (v.x / u.size.w * 0.5 + 0.5) * size;
    let y = (0.5 - v.y / u.size.w * 0.5) * size;
    let z = -v.z;
    var lit = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let px = i32(floor(x)) + dx;
            let py = i32(floor(y)) + dy;
            if (px < 0 || py < 0 || px >= i32(size) || py >= i32(size)) {
                lit += 1.0;
                continue;
            }
            let stored = bitcast<f32>(textureLoad(shadow_map, vec2<i32>(px, py), 0).x);
            // Cleared to 1: nothing drawn there.
            if (stored >= 1.0 || z <= stored * u.p3.x + u.p0.w) {
                lit += 1.0;
            }
        }
    }
    return lit / 9.0;
}

// The sample points of pixel q: direction and point of sample i.
struct Sample {
    dir: vec3<f32>,
    point: vec3<f32>,
};

// Where pixel q's sample set starts in `samples`, and its tangent frame: once per pixel.
struct Frame {
    base: u32,
    tb: mat2x3<f32>,
};

fn frame_at(q: vec2<i32>, n: vec3<f32>) -> Frame {
    var f: Frame;
    f.base = ((u32(q.x % 4) + 4u * u32(q.y % 4)) % u.p1.y) * u.p1.x;
    f.tb = basis(n);
    return f;
}

fn sample_at(f: Frame, i: u32, position: vec3<f32>, n: vec3<f32>) -> Sample {
    let p = samples[f.base + i].xyz;
    var s: Sample;
    let w = f.tb[0] * p.x + f.tb[1] * p.y + n * p.z;
    let len = length(w);
    s.dir = select(n, w / len, len > 0.0);
    s.point = position + s.dir * (length(p) * u.p0.x);
    return s;
}

struct SampleOut {
    @location(0) env: vec4<u32>,
    @location(1) sun: vec4<u32>,
};

// in_a: the cone table, in_b: the irradiance table.
@fragment
fn fs_sample(@builtin(position) frag: vec4<f32>) -> SampleOut {
    var out: SampleOut;
    let q = vec2<i32>(frag.xy);
    let g = ld(g_position, q);
    if (g.w <= 0.0) {
        return out;
    }
    let n = ld(g_normal, q).xyz;
    let albedo = albedo_at(q);
    var gathered = vec3<f32>(0.0);
    var visible_cos = 0.0;
    var all_cos = 0.0;
    var occluded = 0.0;
    // Which samples are occluded, for the bounce pass (bit i: sample i), kept in the sun
    // term's w — exact in f32 up to 24 samples.
    var mask = 0u;
    let f = frame_at(q, n);
    for (var i = 0u; i < u.p1.x; i++) {
        let s = sample_at(f, i, g.xyz, n);
        let c = max(dot(s.dir, n), 0.0);
        all_cos += c;
        if (occluder(s.point).x >= 0) {
            occluded += 1.0;
            if (i < 24u) {
                mask |= 1u << i;
            }
            continue;
        }
        visible_cos += c;
        if (u.p1.w == 1u) {
            gathered += oct_get(in_a, u.p2.z, s.dir) * c;
        }
    }
    let nf = f32(u.p1.x);
    var env = vec3<f32>(0.0);
    if (u.p1.w == 0u) {
        var ao = 1.0;
        if (all_cos > 0.0) {
            ao = visible_cos / all_cos;
        }
        env = albedo / PI * oct_get(in_b, u.p2.w, n) * ao;
    } else {
        env = albedo / PI * gathered * (2.0 * PI / nf);
    }
    out.env = st(vec4<f32>(env, occluded / nf));
    var sun = vec3<f32>(0.0);
    if (u.sun_dir.w > 0.0) {
        let c = dot(n, u.sun_dir.xyz);
        if (c > 0.0) {
            sun = albedo / PI * u.sun_irradiance.xyz * c * sun_lit(g.xyz);
        }
    }
    out.sun = st(vec4<f32>(sun, f32(mask)));
    return out;
}

// What the sender stored at pixel k sends to the receiver at p with normal n: its pixel's
// direct radiance (in_a + in_b) through a patch of `area`, back-facing senders ignored.
fn bounce(p: vec3<f32>, n: vec3<f32>, k: vec2<i32>, area: f32, d_min2: f32) -> vec3<f32> {
    let sender = ld(g_position, k).xyz;
    let sender_n = ld(g_normal, k).xyz;
    let d = sender - p;
    let d2 = dot(d, d);
    if (d2 <= 0.0) {
        return vec3<f32>(0.0);
    }
    let dir = d / sqrt(d2);
    let cos_r = dot(n, dir);
    let cos_s = -dot(sender_n, dir);
    if (cos_r <= 0.0 || cos_s <= 0.0) {
        return vec3<f32>(0.0);
    }
    let light = ld(in_a, k).xyz + ld(in_b, k).xyz;
    return light * (area * cos_s * cos_r / max(d2, d_min2));
}

// in_a: the environment term, in_b: the sun term (both unblurred).
@fragment
fn fs_indirect(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<u32> {
    let q = vec2<i32>(frag.xy);
    let g = ld(g_position, q);
    if (g.w <= 0.0) {
        return st(vec4<f32>(0.0));
    }
    let n = ld(g_normal, q).xyz;
    let albedo = albedo_at(q);
    let nf = f32(u.p1.x);
    let area = u.p0.z * PI * u.p0.x * u.p0.x / nf;
    let d_min2 = u.p0.x * u.p0.x * 0.5;
    var sum = vec3<f32>(0.0);
    // The sampling pass recorded which samples are occluded: only their senders are projected
    // again (no depth tests), one iteration per set bit — the fragments shaded together then
    // loop as often as the most occluded of them, not N times. Beyond 24 samples the rest are
    // tested here.
    var mask = u32(ld(in_b, q).w);
    let f = frame_at(q, n);
    loop {
        if (mask == 0u) {
            break;
        }
        let i = firstTrailingBit(mask);
        mask &= mask - 1u;
        let s = sample_at(f, i, g.xyz, n);
        sum += bounce(g.xyz, n, pixel_of(s.point), area, d_min2);
    }
    for (var i = 24u; i < u.p1.x; i++) {
        let s = sample_at(f, i, g.xyz, n);
        let k = occluder(s.point);
        if (k.x >= 0) {
            sum += bounce(g.xyz, n, k, area, d_min2);
        }
    }
    return st(vec4<f32>(albedo / PI * sum, 1.0));
}

struct Pair {
    @location(0) a: vec4<u32>,
    @location(1) b: vec4<u32>,
};

// One direction of the separable blur of (in_a, in_b); the direction is p3.yz.
@fragment
fn fs_blur(@builtin(position) frag: vec4<f32>) -> Pair {
    var out: Pair;
    let q = vec2<i32>(frag.xy);
    let c = ld(g_position, q);
    if (c.w <= 0.0) {
        return out;
    }
    let cn = ld(g_normal, q).xyz;
    let r = i32(u.p2.y);
    let stride = vec2<i32>(i32(u.p3.y), i32(u.p3.z));
    let inv_sigma = 1.0 / max(0.25 * u.p0.x, 1e-6);
    var acc_a = vec3<f32>(0.0);
    var acc_b = vec3<f32>(0.0);
    var wsum = 0.0;
    for (var i = -r; i <= r; i++) {
        let p = q + stride * i;
        if (p.x < 0 || p.y < 0 || p.x >= i32(u.size.x) || p.y >= i32(u.size.y)) {
            continue;
        }
        let s = ld(g_position, p);
        if (s.w <= 0.0) {
            continue;
        }
        let dd = (s.w - c.w) * inv_sigma;
        let wn = pow(max(dot(cn, ld(g_normal, p).xyz), 0.0), 8.0);
        let wt = exp(-0.5 * dd * dd) * wn;
        acc_a += ld(in_a, p).xyz * wt;
        acc_b += ld(in_b, p).xyz * wt;
        wsum += wt;
    }
    if (wsum > 0.0) {
        out.a = st(vec4<f32>(acc_a / wsum, 1.0));
        out.b = st(vec4<f32>(acc_b / wsum, 1.0));
    } else {
        out.a = textureLoad(in_a, q, 0);
        out.b = textureLoad(in_b, q, 0);
    }
    return out;
}

// in_a: blurred environment term, in_b: blurred bounce, in_c: the sun term. Linear radiance.
@fragment
fn fs_composite(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<u32> {
    let q = vec2<i32>(frag.xy);
    let covered = ld(g_position, q).w > 0.0;
    let c = ld(in_a, q).xyz + ld(in_b, q).xyz + ld(in_c, q).xyz;
    return st(vec4<f32>(c, select(0.0, 1.0, covered)));
}
