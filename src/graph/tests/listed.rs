//! Passes with a work list: an entry that lists texels and a `listed`
//! entry run over them (PassDesc::listed, shared/work_list.wgsl).

use super::*;

/// `main` (8x8) fills the work list; `listed` (64x1) runs over it and also
/// reads `extra`.
fn listing_shader(listed_size: [u32; 3], main_uses_list: bool, list: BindingKind) -> ShaderInfo {
    let mut main: Vec<(&str, BindingKind)> = vec![("src", tex()), ("dst", out(F16))];
    if main_uses_list {
        main.push(("work_list", list.clone()));
    }
    let mut s = shader("sel.wgsl", &main);
    let mut listed = entry("sel.wgsl", "listed", listed_size, &[("src", tex()), ("dst", out(F16)), ("work_list", list), ("extra", tex())]);
    // Bindings of one module keep their numbers across entry points.
    for b in &mut listed.bindings {
        b.binding = match b.name.as_str() {
            "src" => 0,
            "dst" => 1,
            "work_list" => 2,
            _ => 3,
        };
    }
    s.entry_points.push(listed);
    s
}

fn listing_graph(listed: Option<&str>) -> FrameGraph {
    let listed = listed.map(|l| format!(", listed: \"{l}\"")).unwrap_or_default();
    graph(
        &f16(&["a", "b", "c"]),
        &format!(
            "Pass(name: \"gen\", shader: \"gen.wgsl\", bind: {{ \"dst\": \"a\" }}),\n\
             Pass(name: \"gen2\", shader: \"gen.wgsl\", bind: {{ \"dst\": \"c\" }}),\n\
             Pass(name: \"sel\", shader: \"sel.wgsl\"{listed}, bind: {{ \"src\": \"a\", \"dst\": \"b\", \"extra\": \"c\" }}),"
        ),
        "b",
    )
}

#[test]
fn a_listed_pass_binds_the_list_and_what_either_entry_reads() {
    let s = ok_with(&listing_graph(Some("listed")), &[listing_shader([64, 1, 1], true, storage(false))]);
    let p = pass(&s, "sel");
    assert_eq!((p.entry.as_str(), p.listed.as_deref(), p.workgroup_size), ("main", Some("listed"), [8, 8, 1]));
    let targets: Vec<(&str, &Target)> = p.bindings.iter().map(|b| (b.name.as_str(), &b.target)).collect();
    assert!(targets.contains(&("work_list", &Target::WorkList)), "{targets:?}");
    // `extra` is read only by the listed entry, and still orders the passes.
    assert!(targets.iter().any(|(n, _)| *n == "extra"), "{targets:?}");
    assert_eq!(io(&s, "sel"), "a@1 c@1 -> b@1");
}

#[test]
fn a_listed_entry_must_exist() {
    let e = fail_with(&listing_graph(Some("trace")), &[listing_shader([64, 1, 1], true, storage(false))]);
    check(&e, ErrorKind::UnknownEntry, Some("sel"), None, &["`listed: \"trace\"`", "[main, listed]"]);
    // Nor may it be the pass's own entry.
    let mut g = listing_graph(Some("main"));
    g.passes[2].entry = Some("main".into());
    let e = fail_with(&g, &[listing_shader([64, 1, 1], true, storage(false))]);
    check(&e, ErrorKind::UnknownEntry, Some("sel"), None, &["another compute entry point", "than the pass's own"]);
}

#[test]
fn a_listed_entry_takes_the_list_workgroup_size() {
    let e = fail_with(&listing_graph(Some("listed")), &[listing_shader([8, 8, 1], true, storage(false))]);
    check(&e, ErrorKind::UnknownEntry, Some("sel"), None, &["@workgroup_size(8, 8, 1)", "@workgroup_size(64)"]);
}

#[test]
fn a_work_list_needs_both_entries() {
    // Without `listed:`, the shader's two entries leave the pass's ambiguous.
    let e = fail_with(&listing_graph(None), &[listing_shader([64, 1, 1], true, storage(false))]);
    check(&e, ErrorKind::UnknownEntry, Some("sel"), None, &["name one with `entry:`"]);
    // A pass that uses the list but runs nothing over it.
    let mut g = listing_graph(None);
    g.passes[2].entry = Some("listed".into());
    let e = fail_with(&g, &[listing_shader([64, 1, 1], true, storage(false))]);
    check(&e, ErrorKind::WrongAccess, Some("sel"), None, &["no `listed:` entry"]);
    // A listed entry over a list the pass's entry never fills.
    let e = fail_with(&listing_graph(Some("listed")), &[listing_shader([64, 1, 1], false, storage(false))]);
    check(&e, ErrorKind::WrongAccess, Some("sel"), None, &["does not use `work_list`"]);
}

#[test]
fn a_work_list_is_read_write_storage() {
    let e = fail_with(&listing_graph(Some("listed")), &[listing_shader([64, 1, 1], true, storage(true))]);
    assert_eq!((e.kind, e.pass.as_deref()), (ErrorKind::WrongAccess, Some("sel")), "{e}");
    assert!(e.message.contains("var<storage, read_write> WorkList"), "{e}");
}
