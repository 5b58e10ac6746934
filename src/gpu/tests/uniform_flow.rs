//! The fragment stage decides no control flow on a value read from a uniform buffer (docs/benchmarks.md,
//! "The term's cost"): lavapipe inlines such values and compiles the shader again at every
//! pipeline bind, which cost about 2 ms a frame. A data-flow analysis over
//! naga's IR marks values computable from uniform-buffer values and constants alone and
//! reading at least one uniform value (what lavapipe can inline), through expressions, local
//! variables, call arguments and return values; no `if` condition (a loop's exit is one in
//! naga's IR), `break if` or `switch` selector reachable from a fragment entry point may be
//! such a value. Controls: a loop to `globals.counts.x` through a call argument, and the two
//! patterns the shaders had before the fix put back, must be flagged.
mod analysis;

use crate::gpu::shaders;
use analysis::inlinable_decisions;

#[test]
fn fragment_control_flow_reads_no_uniform_value() {
    for source in [
        shaders::balls_source(false),
        shaders::balls_source(true),
        shaders::truth_source(false),
        shaders::truth_source(true),
    ] {
        let found = inlinable_decisions(source);
        assert!(
            found.is_empty(),
            "fragment control flow on globals: {found:?}"
        );
    }
}

#[test]
fn a_loop_over_a_uniform_count_is_flagged() {
    // Control: the pattern that cost a compile a bind, reached through a call argument.
    let source = shaders::balls_source(false).to_string()
        + "
fn count_up(n: u32) -> u32 {
    var s = 0u;
    for (var k = 0u; k < n; k++) { s += k; }
    return s;
}
@fragment
fn fs_control() -> @location(0) vec4<f32> {
    return vec4<f32>(f32(count_up(globals.counts.x)));
}
";
    let found = inlinable_decisions(&source);
    assert!(
        found.iter().any(|d| d.starts_with("count_up:")),
        "not flagged: {found:?}"
    );
}

#[test]
fn the_patterns_before_the_fix_are_flagged() {
    let source = shaders::balls_source(false);
    // The light loop to the uniform count, and the table read's if on the uniform axis
    // size. (The ball loop to the uniform count, the first pattern fixed, went with the
    // full-screen path's nearest_hit.)
    let loop_back = source.replace("k < n_lights;", "k < min(globals.counts.y, MAX_LIGHTS);");
    assert_ne!(loop_back, source, "the light loop moved: update this test");
    let found = inlinable_decisions(&loop_back);
    // The loop is the metal's and the coating's (lighting.wgsl shade_metal, coating.wgsl
    // shade_coating): both must be flagged.
    for function in ["shade_metal:", "shade_coating:"] {
        assert!(
            found.iter().any(|d| d.starts_with(function)),
            "{function} not flagged: {found:?}"
        );
    }
    let if_back = source.replace(
        "    let single = n <= 1u;",
        "    if n <= 1u {\n        return LutSpan(0u, 0u, 0.0);\n    }\n    let single = false;",
    );
    assert_ne!(if_back, source, "lut_texel_span moved: update this test");
    let found = inlinable_decisions(&if_back);
    assert!(
        found.iter().any(|d| d.starts_with("lut_texel_span:")),
        "not flagged: {found:?}"
    );
}
