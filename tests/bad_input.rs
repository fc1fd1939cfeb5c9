//! Bad input through the release binary (issue 16), table-driven: each
//! case must exit 2 without a panic, and its message must name the file
//! (with its line where the input has lines) and the problem. Cases that
//! are valid but were mishandled (a byte order mark) must work.

mod common;

use std::path::Path;
use std::process::Command;

use common::*;

fn glint(args: &[&str]) -> (i32, String) {
    glint_env(args, &[])
}

fn glint_env(args: &[&str], env: &[(&str, &str)]) -> (i32, String) {
    let (code, _, stderr) = run_glint(args, env);
    (code, stderr)
}

fn pfm(path: &Path, header: &str, pixels: &[[f32; 3]]) -> String {
    let mut bytes = header.as_bytes().to_vec();
    for p in pixels {
        for c in p {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    std::fs::write(path, bytes).expect("write pfm");
    path.display().to_string()
}

/// Available memory in GiB from /proc/meminfo, if readable.
fn available_gib() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kib: f64 = text.lines().find(|l| l.starts_with("MemAvailable:"))?.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1048576.0)
}

#[test]
fn bad_input_is_a_clear_error() {
    let dir = scratch("bad-input");
    std::fs::create_dir_all(&dir).unwrap();
    let good = pfm(&dir.join("good.pfm"), "PF\n2 1\n-1.0\n", &[[0.5, 0.5, 0.5], [1.0, 0.0, 0.0]]);
    let nan = pfm(&dir.join("nan.pfm"), "PF\n2 1\n-1.0\n", &[[f32::NAN, 0.5, 0.5], [1.0, 0.0, 0.0]]);
    let inf = pfm(&dir.join("inf.pfm"), "PF\n2 1\n-1.0\n", &[[0.5, 0.5, 0.5], [f32::INFINITY, 0.0, 0.0]]);
    let huge = pfm(&dir.join("huge.pfm"), "PF\n2147483648 2147483648\n-1.0\n", &[]);
    let wide = pfm(&dir.join("wide.pfm"), "PF\n4294967295 1\n-1.0\n", &[]);
    let graph = |name: &str, size: &str| {
        let text = std::fs::read_to_string(repo().join("passes/direct.ron")).unwrap().replacen("Texture(format: Rgba32Float)", &format!("Texture(format: Rgba32Float, size: {size})"), 1);
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path.display().to_string()
    };
    let nan_scale = graph("nan-scale.ron", "Scaled(NaN)");
    let zero_scale = graph("zero-scale.ron", "Scaled(0.0)");
    let empty_fixed = graph("empty-fixed.ron", "Fixed(0, 8)");
    let out = dir.join("x.png").display().to_string();
    // A shader with a 1.6 MB private array (the driver compiled it for
    // over a minute).
    std::fs::create_dir_all(dir.join("shaders")).unwrap();
    std::fs::create_dir_all(dir.join("passes")).unwrap();
    std::fs::write(
        dir.join("shaders/big.wgsl"),
        "@group(0) @binding(0) var out_tex: texture_storage_2d<rgba32float, write>;\nvar<private> big: array<vec4f, 100000>;\n\
         @compute @workgroup_size(8, 8)\nfn main(@builtin(global_invocation_id) id: vec3u) {\n    big[id.x] = vec4f(1.0);\n    textureStore(out_tex, id.xy, big[id.y]);\n}\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("passes/big.ron"),
        "FrameGraph(name: \"big\", resources: { \"out_tex\": Texture(format: Rgba32Float) },\n  passes: [ Pass(name: \"big\", shader: \"big.wgsl\") ], output: \"out_tex\")\n",
    )
    .unwrap();
    let big = dir.join("passes/big.ron").display().to_string();
    // Valid WGSL that naga's SPIR-V writer panics on: a pointer to a struct
    // member passed to a function.
    std::fs::write(
        dir.join("shaders/member.wgsl"),
        "@group(0) @binding(0) var out_tex: texture_storage_2d<rgba32float, write>;\nstruct Pair {\n    a: f32,\n    b: f32,\n}\n\
         fn bump(p: ptr<function, f32>) {\n    *p = *p + 1.0;\n}\n@compute @workgroup_size(8, 8)\nfn main(@builtin(global_invocation_id) id: vec3u) {\n\
         var s = Pair(0.0, 0.0);\n    bump(&s.a);\n    textureStore(out_tex, id.xy, vec4f(s.a));\n}\n",
    )
    .unwrap();
    std::fs::write(dir.join("passes/member.ron"), std::fs::read_to_string(dir.join("passes/big.ron")).unwrap().replace("big", "member")).unwrap();
    let member = dir.join("passes/member.ron").display().to_string();
    let outside = dir.join("passes/outside.ron");
    std::fs::write(&outside, std::fs::read_to_string(dir.join("passes/big.ron")).unwrap().replace("big.wgsl", "/etc/passwd")).unwrap();
    let outside = outside.display().to_string();
    let up = dir.join("passes/up.ron");
    std::fs::write(&up, std::fs::read_to_string(dir.join("passes/big.ron")).unwrap().replace("big.wgsl", "../passes/big.ron")).unwrap();
    let up = up.display().to_string();
    // Meshes: a bad vertex, an out-of-range face, a usemtl a garbage MTL
    // does not define, a directory, a device.
    let mesh_scene = |name: &str, mesh: &str| {
        let path = dir.join(name);
        std::fs::write(&path, format!("Scene(camera: Camera(position: (0.0, 0.0, 3.0), target: (0.0, 0.0, 0.0), vfov_deg: 40.0),\n  objects: [\n    Mesh(path: {mesh:?}),\n  ])\n")).unwrap();
        path.display().to_string()
    };
    std::fs::write(dir.join("badv.obj"), "v 0 0 0\nv 1 0 0\nv 0 x 0\nf 1 2 3\n").unwrap();
    std::fs::write(dir.join("badf.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\n").unwrap();
    std::fs::write(dir.join("garbage.mtl"), "this is not\na material library\n").unwrap();
    std::fs::write(dir.join("usemtl.obj"), "mtllib garbage.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n").unwrap();
    std::fs::create_dir_all(dir.join("adir.obj")).unwrap();
    let badv = mesh_scene("badv.ron", "badv.obj");
    let badf = mesh_scene("badf.ron", "badf.obj");
    let usemtl = mesh_scene("usemtl.ron", "usemtl.obj");
    let adir = mesh_scene("adir.ron", "adir.obj");
    let device = mesh_scene("device.ron", "/dev/zero");
    // Finite but huge: a sphere of radius 1e20, a camera at 3e38, a mesh
    // scaled 1e19.
    let edited = |name: &str, from: &str, to: &str| {
        let text = std::fs::read_to_string(repo().join("scenes/cornell.ron")).unwrap().replacen(from, to, 1);
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path.display().to_string()
    };
    let r20 = edited("r20.ron", "radius: 0.35", "radius: 1e20");
    let ground = edited("ground.ron", "Sphere(center: (-0.4, -0.65, -0.3), radius: 0.35", "Sphere(center: (0.0, -1e8, 0.0), radius: 1e8");
    let cam = edited("cam.ron", "position: (0.0, 0.0, 3.4)", "position: (0.0, 0.0, 3e38)");
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let scaled = dir.join("scaled.ron");
    std::fs::write(&scaled, "Scene(camera: Camera(position: (0.0, 0.0, 3.0), target: (0.0, 0.0, 0.0), vfov_deg: 40.0),\n  objects: [\n    Mesh(path: \"tri.obj\", scale: 1e19),\n  ])\n").unwrap();
    let scaled = scaled.display().to_string();
    let same = dir.join("same.ron");
    std::fs::write(&same, "[Key(time_s: 0.0, position: (1.0, 1.0, 1.0), target: (1.0, 1.0, 1.0))]").unwrap();
    let same = format!("keys:{}", same.display());
    let far = dir.join("far.ron");
    std::fs::write(&far, "[Key(time_s: 0.0, position: (0.0, 0.0, 3e38), target: (0.0, 0.0, 0.0))]").unwrap();
    let far = format!("keys:{}", far.display());
    // (what, args, text the message must hold)
    let cases: Vec<(&str, Vec<&str>, Vec<&str>)> = vec![
        ("a PFM header of 2^31 x 2^31 and no data", vec!["compare", &huge, &huge], vec!["huge.pfm", "2147483648x2147483648"]),
        ("a PFM header wider than the data", vec!["compare", &wide, &good], vec!["wide.pfm", "holds 0 bytes"]),
        ("NaN pixels in a compared image", vec!["compare", &good, &nan], vec!["nan.pfm", "1 pixels hold NaN or infinite values", "x 0, y 0"]),
        ("an infinite pixel in the reference", vec!["compare", &inf, &good], vec!["inf.pfm", "x 1, y 0"]),
        ("--block 0", vec!["compare", &good, &good, "--block", "0"], vec!["--block", "0"]),
        ("a texture Scaled(NaN)", vec!["graph", "check", &nan_scale], vec!["nan-scale.ron:", "Scaled(NaN)", "finite number in (0, 16]"]),
        ("a texture Scaled(0)", vec!["graph", "check", &zero_scale], vec!["zero-scale.ron:", "Scaled(0)"]),
        ("a texture Fixed(0, 8)", vec!["graph", "check", &empty_fixed], vec!["empty-fixed.ron:", "Fixed(0, 8)` is empty"]),
        ("a 1.6 MB private array", vec!["graph", "check", &big], vec!["big.wgsl:2:", "takes 1600000 bytes"]),
        ("a shader path outside the shader folder", vec!["graph", "check", &outside], vec!["outside.ron:2:", "`/etc/passwd` is outside the shader folder"]),
        ("a shader path climbing out with ..", vec!["graph", "check", &up], vec!["up.ron:2:", "`../passes/big.ron` is outside"]),
        ("an OBJ vertex that is not a number", vec!["graph", "check", "passes/direct.ron", "--scene", &badv], vec!["badv.ron:3", "badv.obj:3", "`v 0 x 0` needs three numbers"]),
        ("an OBJ face index out of range", vec!["graph", "check", "passes/direct.ron", "--scene", &badf], vec!["badf.obj:5", "position index 7 is out of range (1..=3 so far)"]),
        ("a usemtl a garbage MTL does not define", vec!["graph", "check", "passes/direct.ron", "--scene", &usemtl], vec!["usemtl.obj:5", "usemtl `red`: no such material"]),
        ("a directory as a mesh", vec!["graph", "check", "passes/direct.ron", "--scene", &adir], vec!["adir.ron:3", "is a directory"]),
        ("/dev/zero as a mesh", vec!["graph", "check", "passes/direct.ron", "--scene", &device], vec!["device.ron:3", "not a regular file"]),
        ("a sphere of radius 1e20", vec!["graph", "check", "passes/direct.ron", "--scene", &r20], vec!["r20.ron:", "`radius` 1e20 is beyond glint's range of 1e15"]),
        ("a sphere of radius 1e8 seen from 1 off its surface", vec!["graph", "check", "passes/direct.ron", "--scene", &ground], vec!["ground.ron:", "radius 1e8 seen from ", "model a large ground or wall as a Quad"]),
        ("a camera at z = 3e38", vec!["graph", "check", "passes/direct.ron", "--scene", &cam], vec!["cam.ron:", "is 3e38 from the camera at (0, 0, 3e38)"]),
        ("a mesh scaled by 1e19", vec!["graph", "check", "passes/direct.ron", "--scene", &scaled], vec!["scaled.ron:3", "beyond glint's range"]),
        ("refine.samples = 4e9 (a loop count beyond its limit)", vec!["graph", "check", "passes/hybrid.ron", "--scene", "scenes/cornell.ron", "--set", "refine.samples=4000000000"], vec!["hybrid.ron:", "pass `refine`", "`samples` = 4000000000 is outside its limit 1..64"]),
        ("lights.samples = 0", vec!["graph", "check", "passes/direct.ron", "--scene", "scenes/cornell.ron", "--set", "lights_area.samples=0"], vec!["direct.ron:", "outside its limit 1..64"]),
        ("--time NaN", vec!["render", "scenes/cornell.ron", "--time", "NaN", "--out", &out], vec!["--time", "finite number of seconds"]),
        ("--dt inf", vec!["render", "scenes/cornell.ron", "--dt", "inf", "--out", &out], vec!["--dt", "finite number of seconds"]),
        ("--camera-path orbit:3e38", vec!["render", "scenes/cornell.ron", "--camera-path", "orbit:3e38", "--out", &out], vec!["orbit:3e38", "within +-360000"]),
        ("a camera key whose target is its position", vec!["render", "scenes/cornell.ron", "--camera-path", &same, "--out", &out], vec!["camera path key 0", "must differ"]),
        ("a camera key at 3e38", vec!["render", "scenes/cornell.ron", "--camera-path", &far, "--out", &out], vec!["camera path key 0", "within 1e15"]),
    ];
    let mut failed = Vec::new();
    for (what, args, needles) in &cases {
        let (code, err) = glint(args);
        if code != 2 || !needles.iter().all(|n| err.contains(n)) {
            failed.push(format!("{what}: exit {code}, message: {err}"));
        }
    }
    // Textures that cannot fit in memory: refused with the figures before
    // anything is created (lavapipe keeps textures in system memory). Only
    // where 16384x16384 of direct.ron (46 GiB) is beyond what is available.
    if gpu().is_some() && available_gib().is_some_and(|g| g < 46.0) {
        let (code, err) = glint(&["render", "scenes/cornell.ron", "--graph", "passes/direct.ron", "--size", "16384x16384", "--frames", "1", "--out", &out]);
        if code != 2 || !err.contains("needs 46.00 GiB of textures") || !err.contains("render smaller") {
            failed.push(format!("16384x16384: exit {code}, message: {err}"));
        }
    }
    // A shader the shader compiler panics on: an error naming it, not a crash.
    if gpu().is_some() {
        let (code, err) = glint(&["render", "scenes/cornell.ron", "--graph", &member, "--size", "8x8", "--out", &out]);
        if code != 2 || !err.contains("member.wgsl") || !err.contains("the shader compiler failed on this shader") {
            failed.push(format!("a pointer to a struct member: exit {code}, message: {err}"));
        }
    }
    assert!(failed.is_empty(), "{} of {} cases failed:\n{}", failed.len(), cases.len() + 2, failed.join("\n"));
    std::fs::remove_dir_all(&dir).ok();
}

/// (what, args, environment, text the message must hold)
type Case<'a> = (&'a str, Vec<&'a str>, Vec<(&'a str, &'a str)>, Vec<&'a str>);

/// Issue 40's cases (bad input, round two): each exits 2 with the file,
/// its line where it has lines, and the problem in the graph's or scene's
/// terms; each failed before its fix (a black image with exit 0, a
/// panic, NaN figures, a silent default).
#[test]
fn round_two_is_a_clear_error() {
    let dir = scratch("bad-input-2");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("x.png").display().to_string();
    let dispatch = |name: &str, size: &str| {
        let text = std::fs::read_to_string(repo().join("passes/direct.ron"))
            .unwrap()
            .replacen("Pass(name: \"lights_area\"", &format!("Pass(name: \"lights_area\", dispatch: {size}"), 1);
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path.display().to_string()
    };
    let huge = dispatch("huge-dispatch.ron", "Fixed(4294967295, 4294967295)");
    let empty = dispatch("empty-dispatch.ron", "Fixed(0, 0)");
    let nan = dispatch("nan-dispatch.ron", "Scaled(NaN)");
    let texels = dir.join("texels.ron");
    let text = std::fs::read_to_string(repo().join("passes/direct.ron")).unwrap();
    std::fs::write(&texels, text.replacen("Pass(name: \"lights_area\"", "Pass(name: \"lights_area\", texels_per_invocation: 65", 1)).unwrap();
    let texels = texels.display().to_string();
    let nan_pfm = pfm(&dir.join("nan.pfm"), "PF\n2 1\n-1.0\n", &[[f32::NAN, 0.5, 0.5], [1.0, 0.0, 0.0]]);
    std::fs::write(dir.join("big.obj"), "v 0 0 0\nv 1e20 0 0\nv 0 1e20 0\nf 1 2 3\n").unwrap();
    let big = dir.join("big.ron");
    std::fs::write(&big, "Scene(camera: Camera(position: (0.0, 0.0, 3.0), target: (0.0, 0.0, 0.0), vfov_deg: 40.0),\n  objects: [\n    Mesh(path: \"big.obj\"),\n  ])\n").unwrap();
    let big = big.display().to_string();
    let mut cases: Vec<Case> = vec![
        ("dispatch Fixed(0, 0)", vec!["graph", "check", &empty], vec![], vec!["empty-dispatch.ron:24:", "pass `lights_area`: dispatch `Fixed(0, 0)` is empty"]),
        ("dispatch Scaled(NaN)", vec!["graph", "check", &nan], vec![], vec!["nan-dispatch.ron:24:", "dispatch `Scaled(NaN)`: the scale must be a finite number"]),
        ("texels_per_invocation: 65", vec!["graph", "check", &texels], vec![], vec!["texels.ron:24:", "`texels_per_invocation` is 65; give 1 to 64"]),
        ("an OBJ vertex at 1e20", vec!["graph", "check", "passes/direct.ron", "--scene", &big], vec![], vec!["big.ron:3", "the mesh reaches 1e20 from its origin", "beyond glint's range"]),
        ("bench stress --target-ms 1e300", vec!["bench", "stress", "scenes/cornell.ron", "--graph", "passes/direct.ron", "--target-ms", "1e300"], vec![], vec!["--target-ms 1e300", "at most 60000"]),
    ];
    for value in ["0", "-1", "abc", "inf", "NaN", ""] {
        cases.push(("GLINT_GPU_TIMEOUT_S", vec!["render", "scenes/cornell.ron", "--size", "8x8", "--out", &out], vec![("GLINT_GPU_TIMEOUT_S", value)], vec!["GLINT_GPU_TIMEOUT_S", "above 0"]));
    }
    if gpu().is_some() {
        cases.push((
            "dispatch Fixed(4294967295, 4294967295)",
            vec!["render", "scenes/cornell.ron", "--graph", &huge, "--size", "8x8", "--out", &out],
            vec![],
            vec!["huge-dispatch.ron:24:", "pass `lights_area`: its dispatch of 4294967295x4294967295 invocations", "at most 65535 a side"],
        ));
        cases.push((
            "trade --reference with a NaN pixel",
            vec!["trade", "scenes/cornell.ron", "--graphs", "passes/direct.ron", "--reference", &nan_pfm, "--size", "2x1", "--frames", "1", "--out", &out],
            vec![],
            vec!["nan.pfm", "1 pixels hold NaN or infinite values"],
        ));
    }
    // A graph of one pass in a folder of its own (passes/, shaders/).
    let ws = dir.join("ws");
    std::fs::create_dir_all(ws.join("shaders/shared")).unwrap();
    std::fs::create_dir_all(ws.join("passes")).unwrap();
    let one_pass = |name: &str| {
        let path = ws.join(format!("passes/{name}.ron"));
        let text = format!("FrameGraph(name: \"{name}\", resources: {{ \"out_tex\": Texture(format: Rgba32Float) }},\n  passes: [ Pass(name: \"{name}\", shader: \"{name}.wgsl\") ], output: \"out_tex\")\n");
        std::fs::write(&path, text).unwrap();
        path.display().to_string()
    };
    std::fs::write(
        ws.join("shaders/wide.wgsl"),
        "@group(0) @binding(0) var out_tex: texture_storage_2d<rgba32float, write>;\n\n@compute @workgroup_size(1024, 1024)\nfn main(@builtin(global_invocation_id) id: vec3u) {\n    textureStore(out_tex, id.xy, vec4f(1.0));\n}\n",
    )
    .unwrap();
    let wide = one_pass("wide");
    let wrong_param = dir.join("wrong-param.ron");
    std::fs::write(&wrong_param, text.replacen("params: { jitter: 1 }", "params: { jitter: \"yes\" }", 1)).unwrap();
    let wrong_param = wrong_param.display().to_string();
    let deep = dir.join("deep.ron");
    std::fs::write(&deep, text.replacen("params: { jitter: 1 }", &format!("params: {{ {}{}: 1 }}", "[".repeat(300), "]".repeat(300)), 1)).unwrap();
    let deep = deep.display().to_string();
    let realtime = std::fs::read_to_string(repo().join("passes/realtime.ron")).unwrap();
    let constant = dir.join("constant.ron");
    std::fs::write(&constant, realtime.replacen("constants: { STEP: 1,", "constants: { STEP: 1e30,", 1)).unwrap();
    let constant = constant.display().to_string();
    cases.extend([
        ("a param of the wrong type", vec!["graph", "check", &wrong_param], vec![], vec!["wrong-param.ron:21:", "a param value: a number", "found the string \"yes\""]),
        ("brackets nested 300 deep", vec!["graph", "check", &deep], vec![], vec!["deep.ron:21:", "nested too deep"]),
        ("an override of 1e30", vec!["graph", "check", &constant, "--scene", "scenes/cornell.ron"], vec![], vec!["constant.ron:", "pass `atrous_1`: constant `STEP` = 1e30 does not fit the shader's `override STEP: i32`"]),
        ("WGPU_BACKEND=gl", vec!["render", "scenes/cornell.ron", "--size", "8x8", "--out", &out], vec![("WGPU_BACKEND", "gl")], vec!["WGPU_BACKEND=gl: glint does not run on wgpu's GL backend"]),
    ]);
    if gpu().is_some() {
        cases.push(("a 1024x1024 workgroup", vec!["render", "scenes/cornell.ron", "--graph", &wide, "--size", "8x8", "--out", &out], vec![], vec!["wide.wgsl:3:", "`@workgroup_size(1024, 1024, 1)` of `main` makes 1048576 invocations a workgroup"]));
    }
    // A link inside the shader folder that leads out of it.
    #[cfg(unix)]
    let link_graph = {
        std::os::unix::fs::symlink("/etc/passwd", ws.join("shaders/evil.wgsl")).unwrap();
        one_pass("evil")
    };
    #[cfg(unix)]
    cases.push(("a shader linked out of the shader folder", vec!["graph", "check", &link_graph], vec![], vec!["evil.wgsl", "leads to /etc/passwd, outside the shader folder"]));
    // A device as the scene or the graph (read forever before) and a
    // folder as the scene.
    #[cfg(unix)]
    let zero = {
        let link = dir.join("zero.ron");
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        link.display().to_string()
    };
    #[cfg(unix)]
    cases.extend([
        ("/dev/zero as the scene", vec!["render", "/dev/zero", "--out", &out], vec![], vec!["/dev/zero: is not a regular file", "scene file"]),
        ("a link to /dev/zero as the graph", vec!["graph", "check", &zero], vec![], vec!["zero.ron: is not a regular file", "graph file"]),
    ]);
    cases.push(("a folder as the scene", vec!["render", "scenes", "--out", &out], vec![], vec!["scenes: is a folder; give the scene file"]));
    let mut failed = Vec::new();
    for (what, args, env, needles) in &cases {
        let (code, err) = glint_env(args, env);
        if code != 2 || !needles.iter().all(|n| err.contains(n)) || err.contains("root:") {
            failed.push(format!("{what}: exit {code}, message: {err}"));
        }
    }
    assert!(failed.is_empty(), "{} of {} cases failed:\n{}", failed.len(), cases.len(), failed.join("\n"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn adapter_filters_that_match_nothing_say_so() {
    let (code, err) = glint_env(&["render", "scenes/cornell.ron", "--out", "target/x.png"], &[("WGPU_BACKEND", "bogus")]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("WGPU_BACKEND=`bogus` names no backend"), "{err}");
    if gpu().is_some() {
        let (code, err) = glint_env(&["render", "scenes/cornell.ron", "--out", "target/x.png"], &[("WGPU_ADAPTER_NAME", "nosuch")]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("WGPU_ADAPTER_NAME=`nosuch` matches none of the adapters there are: `llvmpipe") || err.contains("matches none"), "{err}");
    }
}

#[test]
fn quiet_surprises_are_said() {
    if gpu().is_none() {
        return;
    }
    let dir = scratch("surprises");
    std::fs::create_dir_all(&dir).unwrap();
    let empty = dir.join("empty.ron");
    std::fs::write(&empty, "Scene(camera: Camera(position: (0.0, 0.0, 3.0), target: (0.0, 0.0, 0.0), vfov_deg: 40.0))").unwrap();
    let out = dir.join("x.png").display().to_string();
    let (code, err) = glint(&["render", &empty.display().to_string(), "--graph", "passes/direct.ron", "--size", "16x16", "--out", &out]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("has no objects and 0 lights: the image is the background"), "{err}");
    // The size printed is the written image's, not the render's.
    let out_cmd = Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(["render", "scenes/cornell.ron", "--graph", "tests/graphs/samplers.ron", "--size", "16x16", "--out", &out])
        .current_dir(repo())
        .env("WGPU_BACKEND", "vulkan")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out_cmd.stdout);
    assert!(stdout.contains("(1024x7)"), "{stdout}");
    // --hitdist only writes EXR or PFM, and says so before benchmarking.
    let (code, err) = glint(&["bench", "rays", "--obj", "scenes/meshes/knot.obj", "--camera", "0,0,5,0,0,0,45", "--size", "16x16", "--hitdist", "x.txt"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("x.txt") && err.contains("--hitdist writes an .exr or a .pfm"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_byte_order_mark_is_not_an_error() {
    let dir = scratch("bom");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("bom.ron");
    std::fs::write(&scene, format!("\u{feff}{}", std::fs::read_to_string(repo().join("scenes/cornell.ron")).unwrap())).unwrap();
    let (code, err) = glint(&["graph", "check", "passes/direct.ron", "--scene", &scene.display().to_string()]);
    assert_eq!(code, 0, "{err}");
    std::fs::remove_dir_all(&dir).ok();
}
