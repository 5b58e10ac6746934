//! The GPU ball named once: [`gpu_ball!`] turns the one list of the ball's members (in
//! `uniforms.rs`: each a named `f32`, `u32` or `[f32; 3]`, never a lane of a vector) into
//! the `repr(C)` struct [`GpuBall`](super::uniforms::GpuBall) and the table
//! [`BALL_MEMBERS`](super::uniforms::BALL_MEMBERS) of names, offsets and types. From that
//! table come the vertex layout of a ball's quad ([`attributes`]) and the WGSL that carries
//! the ball from the vertex buffer to the fragment stage ([`wgsl`]: `struct Ball`, the
//! vertex input `BallIn`, the flat varyings `BallOut`, `ball_out` and `ball_of`), which
//! `shaders/types.wgsl` holds between the markers of the generated constants
//! (src/gpu/tests/boundary.rs checks the text and, with naga, the layout against `vs_ball`).
//! Adding a member is its line in the list, its value in `uniforms::balls`, and the
//! blessed block.
//!
//! The members travel packed: each run of members of one scalar kind within one 16-byte
//! row of the struct is one vertex attribute and one flat varying (a vertex stage takes at
//! most 16 attributes), unpacked by name in `ball_of`.

/// A member's type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum BallType {
    /// `f32`.
    F32,
    /// `u32`.
    U32,
    /// `vec3<f32>` (`[f32; 3]`).
    Vec3F32,
}

impl BallType {
    /// The type as WGSL writes it.
    #[cfg(test)]
    pub(crate) const fn wgsl(self) -> &'static str {
        match self {
            BallType::F32 => "f32",
            BallType::U32 => "u32",
            BallType::Vec3F32 => "vec3<f32>",
        }
    }

    /// Its scalars.
    const fn components(self) -> u32 {
        match self {
            BallType::Vec3F32 => 3,
            _ => 1,
        }
    }

    /// Whether its scalars are floats.
    const fn float(self) -> bool {
        !matches!(self, BallType::U32)
    }
}

/// The Rust types a member may have, and their [`BallType`].
pub(crate) trait BallField {
    /// The member's type.
    const TYPE: BallType;
}

impl BallField for f32 {
    const TYPE: BallType = BallType::F32;
}
impl BallField for u32 {
    const TYPE: BallType = BallType::U32;
}
impl BallField for [f32; 3] {
    const TYPE: BallType = BallType::Vec3F32;
}

/// One member of the GPU ball: its name, byte offset and type.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(not(test), allow(dead_code))] // read by the tests
pub(crate) struct BallMember {
    /// The member's name, the same in Rust and WGSL.
    pub name: &'static str,
    /// `offset_of` it in the Rust struct (and the WGSL one).
    pub offset: usize,
    /// Its type.
    pub ty: BallType,
}

/// The struct `GpuBall` of the listed members (each with its doc comment) and the table
/// `BALL_MEMBERS` of them.
macro_rules! gpu_ball {
    (
        $(#[$outer:meta])*
        struct GpuBall { $($(#[doc = $doc:literal])* $name:ident: $ty:ty,)* }
    ) => {
        $(#[$outer])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
        pub(crate) struct GpuBall {
            $($(#[doc = $doc])* pub $name: $ty,)*
        }

        /// Every member of [`GpuBall`], in order: what its WGSL twins and the vertex layout
        /// of a ball's quad are generated from (`gpu::ball`).
        pub(crate) const BALL_MEMBERS: &[$crate::gpu::ball::BallMember] = &[$(
            $crate::gpu::ball::BallMember {
                name: stringify!($name),
                offset: std::mem::offset_of!(GpuBall, $name),
                ty: <$ty as $crate::gpu::ball::BallField>::TYPE,
            },
        )*];
    };
}
pub(crate) use gpu_ball;

/// The vertex attribute (or flat varying) member `k` of `members` travels in, and its
/// first lane there: a new attribute starts where the scalar kind changes or a 16-byte
/// row begins.
const fn packing(members: &[BallMember]) -> ([usize; 64], [u32; 64], usize) {
    let (mut attribute, mut lane) = ([0; 64], [0; 64]);
    let mut count = 0;
    let mut k = 0;
    while k < members.len() {
        let m = members[k];
        let joins = k > 0 && {
            let p = members[k - 1];
            p.ty.float() == m.ty.float() && p.offset / 16 == m.offset / 16
        };
        if joins {
            attribute[k] = attribute[k - 1];
            lane[k] = lane[k - 1] + members[k - 1].ty.components();
        } else {
            attribute[k] = count;
            lane[k] = 0;
            count += 1;
        }
        k += 1;
    }
    (attribute, lane, count)
}

/// The number of vertex attributes the members travel in.
pub(crate) const fn attribute_count(members: &[BallMember]) -> usize {
    packing(members).2
}

/// The scalar kind and the scalars of attribute `a`.
const fn attribute_shape(members: &[BallMember], a: usize) -> (bool, u32, usize) {
    let (attribute, _, _) = packing(members);
    let (mut float, mut scalars, mut first) = (true, 0, usize::MAX);
    let mut k = 0;
    while k < members.len() {
        if attribute[k] == a {
            float = members[k].ty.float();
            scalars += members[k].ty.components();
            if first == usize::MAX {
                first = k;
            }
        }
        k += 1;
    }
    (float, scalars, first)
}

/// The vertex attributes of a ball's quad: the quad's bounds (`rect`, location 0, at
/// `rect_offset`), then each packed run of members at location `1 + a`, offset by
/// `ball_offset` (where the ball sits in the instance).
pub(crate) const fn attributes<const N: usize>(
    members: &[BallMember],
    rect_offset: u64,
    ball_offset: u64,
) -> [wgpu::VertexAttribute; N] {
    let mut out = [wgpu::VertexAttribute {
        format: wgpu::VertexFormat::Float32x4,
        offset: rect_offset,
        shader_location: 0,
    }; N];
    let mut a = 0;
    while a + 1 < N {
        let (float, scalars, first) = attribute_shape(members, a);
        let format = match (float, scalars) {
            (true, 1) => wgpu::VertexFormat::Float32,
            (true, 2) => wgpu::VertexFormat::Float32x2,
            (true, 3) => wgpu::VertexFormat::Float32x3,
            (true, _) => wgpu::VertexFormat::Float32x4,
            (false, 1) => wgpu::VertexFormat::Uint32,
            (false, 2) => wgpu::VertexFormat::Uint32x2,
            (false, 3) => wgpu::VertexFormat::Uint32x3,
            (false, _) => wgpu::VertexFormat::Uint32x4,
        };
        out[a + 1] = wgpu::VertexAttribute {
            format,
            offset: ball_offset + members[first].offset as u64,
            shader_location: a as u32 + 1,
        };
        a += 1;
    }
    out
}

/// The WGSL type of attribute `a`.
#[cfg(test)]
fn attribute_wgsl(members: &[BallMember], a: usize) -> String {
    let (float, scalars, _) = attribute_shape(members, a);
    let scalar = if float { "f32" } else { "u32" };
    match scalars {
        1 => scalar.to_string(),
        n => format!("vec{n}<{scalar}>"),
    }
}

/// The WGSL of the ball from `members`: `struct Ball` (the members by name, the layout of
/// [`GpuBall`](super::uniforms::GpuBall)), the vertex input `BallIn` (`rect`, then the
/// packed attributes `ball_A`), the flat varyings `BallOut` (`position`, the loop
/// `counts`, the packed attributes), `ball_out` (the vertex stage's copy) and `ball_of`
/// (the members unpacked by name; the term the pipeline's where `BALL_TERM` names one).
#[cfg(test)]
pub(crate) fn wgsl(members: &[BallMember]) -> Vec<String> {
    let (attribute, lane, count) = packing(members);
    let mut out = vec!["struct Ball {".to_string()];
    for m in members {
        out.push(format!("    {}: {},", m.name, m.ty.wgsl()));
    }
    out.push("}".into());
    out.push(String::new());
    out.push(
        "// The ball's members as a quad's instance attributes (BallInstance::LAYOUT).".into(),
    );
    out.push("struct BallIn {".into());
    out.push("    @location(0) rect: vec4<f32>,".into());
    for a in 0..count {
        let ty = attribute_wgsl(members, a);
        out.push(format!("    @location({}) ball_{a}: {ty},", a + 1));
    }
    out.push("}".into());
    out.push(String::new());
    out.push(
        "// A quad's fragment: its ball as flat varyings (a fragment shades only its own".into(),
    );
    out.push("// ball, so it reads no per-ball buffer: a flat varying is a broadcast).".into());
    out.push("struct BallOut {".into());
    out.push("    @builtin(position) position: vec4<f32>,".into());
    out.push("    @location(0) @interpolate(flat) counts: vec2<u32>,".into());
    for a in 0..count {
        let ty = attribute_wgsl(members, a);
        out.push(format!(
            "    @location({}) @interpolate(flat) ball_{a}: {ty},",
            a + 1
        ));
    }
    out.push("}".into());
    out.push(String::new());
    out.push("fn ball_out(in: BallIn, position: vec4<f32>, counts: vec2<u32>) -> BallOut {".into());
    out.push("    var out: BallOut;".into());
    out.push("    out.position = position;".into());
    out.push("    out.counts = counts;".into());
    for a in 0..count {
        out.push(format!("    out.ball_{a} = in.ball_{a};"));
    }
    out.push("    return out;".into());
    out.push("}".into());
    out.push(String::new());
    out.push("fn ball_of(in: BallOut) -> Ball {".into());
    out.push("    var b: Ball;".into());
    const LANES: [&str; 4] = ["x", "y", "z", "w"];
    for (k, m) in members.iter().enumerate() {
        let a = attribute[k];
        let (_, scalars, _) = attribute_shape(members, a);
        let n = m.ty.components();
        let value = if scalars == n {
            format!("in.ball_{a}")
        } else {
            let l = lane[k] as usize;
            format!("in.ball_{a}.{}", LANES[l..l + n as usize].concat())
        };
        out.push(format!("    b.{} = {value};", m.name));
    }
    if members.iter().any(|m| m.name == "term") {
        out.push("    b.term = select(b.term, BALL_TERM, BALL_TERM != 0u);".into());
    }
    out.push("    return b;".into());
    out.push("}".into());
    out
}
