//! Passes that take their texels from a tile pool (shared/tile_pool.wgsl).

use super::*;

fn pooled_shader(pool: BindingKind) -> ShaderInfo {
    shader("pool.wgsl", &[("src", tex()), ("dst", out(F16)), ("tile_pool", pool)])
}

fn pooled_graph(listed: bool) -> FrameGraph {
    let listed = if listed { ", listed: \"listed\"" } else { "" };
    graph(
        &f16(&["a", "b"]),
        &format!(
            "Pass(name: \"gen\", shader: \"gen.wgsl\", bind: {{ \"dst\": \"a\" }}),\n\
             Pass(name: \"pool\", shader: \"pool.wgsl\"{listed}, bind: {{ \"src\": \"a\", \"dst\": \"b\" }}),"
        ),
        "b",
    )
}

#[test]
fn a_pass_binds_its_tile_pool_by_name() {
    let s = ok_with(&pooled_graph(false), &[pooled_shader(storage(false))]);
    let targets: Vec<(&str, &Target)> = pass(&s, "pool").bindings.iter().map(|b| (b.name.as_str(), &b.target)).collect();
    assert!(targets.contains(&("tile_pool", &Target::TilePool)), "{targets:?}");
    assert_eq!(io(&s, "pool"), "a@1 -> b@1");
}

#[test]
fn a_read_only_tile_pool_is_refused() {
    let e = fail_with(&pooled_graph(false), &[pooled_shader(storage(true))]);
    let at = Location { file: "pool.wgsl".into(), line: 3, col: 0 };
    check(&e, ErrorKind::WrongAccess, Some("pool"), Some(at), &["`tile_pool`", "read_write"]);
}

#[test]
fn a_pooled_pass_has_no_work_list() {
    let mut s = pooled_shader(storage(false));
    s.entry_points.push(entry("pool.wgsl", "listed", [64, 1, 1], &[("src", tex()), ("dst", out(F16)), ("tile_pool", storage(false))]));
    let e = fail_with(&pooled_graph(true), &[s]);
    check(&e, ErrorKind::WrongAccess, Some("pool"), None, &["`tile_pool`", "`listed:`"]);
}

#[test]
fn a_pooled_pass_covers_the_render_size() {
    let shaders = [pooled_shader(storage(false))];
    // Writing a half-size texture.
    let mut g = pooled_graph(false);
    let half = graph(
        "\"a\": Texture(format: Rgba16Float),\n\"b\": Texture(format: Rgba16Float, size: Scaled(0.5)),\n",
        "Pass(name: \"gen\", shader: \"gen.wgsl\", bind: { \"dst\": \"a\" }),\n\
         Pass(name: \"pool\", shader: \"pool.wgsl\", bind: { \"src\": \"a\", \"dst\": \"b\" }),",
        "b",
    );
    let e = fail_with(&half, &shaders);
    check(&e, ErrorKind::BadSize, Some("pool"), None, &["`b`", "`tile_pool`"]);
    // Several texels an invocation.
    g.passes[1].texels_per_invocation = Some(4);
    let e = fail_with(&g, &shaders);
    check(&e, ErrorKind::BadSize, Some("pool"), None, &["`texels_per_invocation`", "`tile_pool`"]);
}
