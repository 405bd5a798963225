// The viewer's scene: the environment map as background, then the meshes with interpolated
// per-vertex colours (a textured object's diffuse share multiplied by its albedo per pixel). Display transform identical to the CPU renderer (vcut_shade::image):
// exposure, ACES filmic (Narkowicz's fit), sRGB transfer function.

struct Uniforms {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    // Map-from-world rotation of the environment (columns).
    env_x: vec4<f32>,
    env_y: vec4<f32>,
    env_z: vec4<f32>,
    // exposure, environment intensity, viewport width, viewport height (as in `viewport`)
    params: vec4<f32>,
    // x: tone map mesh colours (1) or show them as they are (0); y: encode sRGB in the shader
    // (1: the target is a linear-format texture) or leave it to the target format (0);
    // z, w: environment map width, height.
    flags: vec4<u32>,
    // The region drawn into: x, y, width, height (pixels).
    viewport: vec4<f32>,
};

@group(0) @binding(0) var<uniform> u: Uniforms;
@group(0) @binding(1) var env_tex: texture_2d<f32>;

const PI: f32 = 3.14159265358979;

fn aces(x: f32) -> f32 {
    let y = (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);
    return clamp(y, 0.0, 1.0);
}

fn srgb(y: f32) -> f32 {
    if (y <= 0.0031308) {
        return 12.92 * y;
    }
    return 1.055 * pow(y, 1.0 / 2.4) - 0.055;
}

fn display_radiance(c: vec3<f32>) -> vec3<f32> {
    let x = max(c * u.params.x, vec3<f32>(0.0));
    var y = vec3<f32>(aces(x.x), aces(x.y), aces(x.z));
    if (u.flags.y == 1u) {
        y = vec3<f32>(srgb(y.x), srgb(y.y), srgb(y.z));
    }
    return y;
}

fn display_colour(c: vec3<f32>) -> vec3<f32> {
    // Already sRGB-encoded: undo the target's encoding when it applies one.
    if (u.flags.y == 1u) {
        return clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
    }
    return pow(clamp(c, vec3<f32>(0.0), vec3<f32>(1.0)), vec3<f32>(2.2));
}

// ---- background ----

struct BgOut {
    @builtin(position) pos: vec4<f32>,
};

@vertex
fn vs_background(@builtin(vertex_index) i: u32) -> BgOut {
    // One triangle covering the screen.
    let x = f32((i << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(i & 2u) * 2.0 - 1.0;
    var out: BgOut;
    out.pos = vec4<f32>(x, y, 1.0, 1.0);
    return out;
}

fn texel(x: i32, y: i32) -> vec3<f32> {
    return textureLoad(env_tex, vec2<i32>(x, y), 0).xyz;
}

// Bilinear lat-long lookup exactly as vcut_envmap::Layout::bilinear: wraps in u, clamps in v.
fn env_radiance(world: vec3<f32>) -> vec3<f32> {
    let d = u.env_x.xyz * world.x + u.env_y.xyz * world.y + u.env_z.xyz * world.z;
    let len = length(d);
    if (len <= 0.0) {
        return vec3<f32>(0.0);
    }
    var uu = atan2(d.x, -d.z) / (2.0 * PI);
    if (uu < 0.0) {
        uu = uu + 1.0;
    }
    if (uu >= 1.0) {
        uu = uu - 1.0;
    }
    let vv = acos(clamp(d.y / len, -1.0, 1.0)) / PI;
    let w = i32(u.flags.z);
    let h = i32(u.flags.w);
    let px = uu * f32(w) - 0.5;
    let py = clamp(vv * f32(h) - 0.5, 0.0, f32(h - 1));
    let x0 = floor(px);
    let fx = px - x0;
    let y0 = min(floor(py), f32(h - 1));
    let fy = py - y0;
    let xa = ((i32(x0) % w) + w) % w;
    let xb = ((i32(x0) + 1) % w + w) % w;
    let ya = i32(y0);
    let yb = min(ya + 1, h - 1);
    let c = texel(xa, ya) * ((1.0 - fx) * (1.0 - fy)) + texel(xb, ya) * (fx * (1.0 - fy))
        + texel(xa, yb) * ((1.0 - fx) * fy) + texel(xb, yb) * (fx * fy);
    return c * u.params.y;
}

fn background(pos: vec4<f32>) -> vec4<f32> {
    let x = (pos.x - u.viewport.x) / u.viewport.z;
    let y = (pos.y - u.viewport.y) / u.viewport.w;
    let ndc = vec4<f32>(x * 2.0 - 1.0, 1.0 - y * 2.0, 1.0, 1.0);
    let far = u.inv_view_proj * ndc;
    let dir = far.xyz / far.w - u.eye.xyz;
    return vec4<f32>(display_radiance(env_radiance(dir)), 1.0);
}

@fragment
fn fs_background(in: BgOut) -> @location(0) vec4<f32> {
    return background(in.pos);
}

// A per-pixel linear image of the viewport (the screen-space methods' output, 32-bit floats
// packed as Rgba32Uint; w: covered), displayed over the background.
@group(1) @binding(0) var image: texture_2d<u32>;

@fragment
fn fs_image(in: BgOut) -> @location(0) vec4<f32> {
    let c = bitcast<vec4<f32>>(textureLoad(image, vec2<i32>(in.pos.xy - u.viewport.xy), 0));
    if (c.w > 0.5) {
        return vec4<f32>(display_radiance(c.xyz), 1.0);
    }
    return background(in.pos);
}

// ---- meshes ----

// The object's albedo texture (a white texel when it has none), sampled bilinearly, repeating,
// sRGB-decoded by its format: what the CPU renderer's Texture::sample computes.
@group(1) @binding(0) var albedo_tex: texture_2d<f32>;
@group(1) @binding(1) var albedo_sampler: sampler;

struct MeshOut {
    @builtin(position) pos: vec4<f32>,
    @location(0) colour: vec3<f32>,
    @location(1) textured: vec3<f32>,
    @location(2) uv: vec2<f32>,
};

@vertex
fn vs_mesh(
    @location(0) position: vec3<f32>,
    @location(1) colour: vec3<f32>,
    @location(2) textured: vec3<f32>,
    @location(3) uv: vec2<f32>,
) -> MeshOut {
    var out: MeshOut;
    out.pos = u.view_proj * vec4<f32>(position, 1.0);
    out.colour = colour;
    out.textured = textured;
    out.uv = uv;
    return out;
}

@fragment
fn fs_mesh(in: MeshOut) -> @location(0) vec4<f32> {
    // Sampled unconditionally (uniform control flow); `textured` is zero where it does not apply.
    let albedo = textureSample(albedo_tex, albedo_sampler, in.uv).xyz;
    let c = in.colour + in.textured * albedo;
    if (u.flags.x == 1u) {
        return vec4<f32>(display_radiance(c), 1.0);
    }
    return vec4<f32>(display_colour(c), 1.0);
}

// ---- leaves: two-sided, each side its own radiance ----

struct LeafOut {
    @builtin(position) pos: vec4<f32>,
    @location(0) front: vec3<f32>,
    @location(1) back: vec3<f32>,
};

@vertex
fn vs_leaf(@location(0) position: vec3<f32>, @location(1) front: vec3<f32>, @location(2) back: vec3<f32>) -> LeafOut {
    var out: LeafOut;
    out.pos = u.view_proj * vec4<f32>(position, 1.0);
    out.front = front;
    out.back = back;
    return out;
}

@fragment
fn fs_leaf(in: LeafOut, @builtin(front_facing) front_facing: bool) -> @location(0) vec4<f32> {
    return vec4<f32>(display_radiance(select(in.back, in.front, front_facing)), 1.0);
}
