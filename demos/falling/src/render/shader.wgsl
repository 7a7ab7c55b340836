// Shaded instanced meshes and coloured lines. Colours are written as they
// are: the targets are non-sRGB (Rgba8Unorm / Bgra8Unorm), as egui wants.

struct Globals {
    view_proj: mat4x4<f32>,
    // xyz: unit direction towards the light.
    light_dir: vec4<f32>,
    // xyz: the eye's position.
    eye: vec4<f32>,
};

@group(0) @binding(0) var<uniform> globals: Globals;

struct MeshIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    // The instance's model matrix, column by column, then its colour.
    @location(2) m0: vec4<f32>,
    @location(3) m1: vec4<f32>,
    @location(4) m2: vec4<f32>,
    @location(5) m3: vec4<f32>,
    @location(6) color: vec4<f32>,
};

struct MeshOut {
    @builtin(position) clip: vec4<f32>,
    // Zero for flat shading (see fs_mesh).
    @location(0) normal: vec3<f32>,
    @location(1) color: vec4<f32>,
    @location(2) world: vec3<f32>,
};

@vertex
fn vs_mesh(v: MeshIn) -> MeshOut {
    let model = mat4x4<f32>(v.m0, v.m1, v.m2, v.m3);
    var out: MeshOut;
    let world = model * vec4<f32>(v.position, 1.0);
    out.clip = globals.view_proj * world;
    out.world = world.xyz;
    // Models are rotations and translations, plus an axis-aligned scale for
    // the floor: the model's linear part keeps normals' directions then.
    out.normal = (model * vec4<f32>(v.normal, 0.0)).xyz;
    out.color = v.color;
    return out;
}

@fragment
fn fs_mesh(in: MeshOut) -> @location(0) vec4<f32> {
    // Vertices with a zero normal ask for the triangle's own: the plane of
    // the interpolated positions, turned towards the eye (only front faces
    // are drawn). Flat triangles can then share their vertices.
    let face = cross(dpdx(in.world), dpdy(in.world));
    let toward_eye = select(face, -face, dot(face, globals.eye.xyz - in.world) < 0.0);
    let n = normalize(select(in.normal, toward_eye, dot(in.normal, in.normal) < 0.25));
    let diffuse = max(dot(n, globals.light_dir.xyz), 0.0);
    // A sky/ground hemisphere term so faces turned from the light keep shape.
    let ambient = 0.22 + 0.12 * n.y;
    return vec4<f32>(in.color.rgb * (ambient + 0.72 * diffuse), 1.0);
}

struct LineIn {
    @location(0) position: vec3<f32>,
    @location(1) color: vec4<f32>,
};

struct LineOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
};

@vertex
fn vs_line(v: LineIn) -> LineOut {
    var out: LineOut;
    out.clip = globals.view_proj * vec4<f32>(v.position, 1.0);
    out.color = v.color;
    return out;
}

@fragment
fn fs_line(in: LineOut) -> @location(0) vec4<f32> {
    return in.color;
}
