//! Bad input through the `glint` binary: a one-paragraph error naming the
//! file and line, exit code 2, never a panic.

mod common;


use common::{repo, scratch};

fn glint(args: &[&str]) -> (i32, String, String) {
    common::run_glint(args, &[])
}

fn write(dir: &std::path::Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_string_lossy().into_owned()
}

#[test]
fn graph_check_shows_the_schedule_with_area_light_work_culled() {
    let (code, out, err) = glint(&["graph", "check", "passes/direct.ron", "--scene", "scenes/cornell-point.ron"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("lights_area: requires AreaLights"), "{out}");
    assert!(out.contains("lights_point"), "{out}");
    let (code, out, _) = glint(&["graph", "check", "passes/direct.ron", "--dot"]);
    assert_eq!(code, 0);
    assert!(out.starts_with("digraph"), "{out}");
}

#[test]
fn hybrid_graph_drops_the_mask_passes_without_area_lights() {
    let (code, out, err) = glint(&["graph", "check", "passes/hybrid.ron", "--scene", "scenes/cornell-point.ron"]);
    assert_eq!(code, 0, "{err}");
    for pass in ["sobel", "blur_h", "blur_v", "threshold", "refine"] {
        assert!(out.contains(&format!("{pass}: requires AreaLights; the scene has none")), "{pass} not culled:\n{out}");
    }
    // The first light pass stays: it seeds `lit` (there is no albedo pass).
    assert!(out.contains("lights_area (lights.wgsl:first)"), "{out}");
    let (code, out, _) = glint(&["graph", "check", "passes/hybrid.ron", "--scene", "scenes/cornell.ron"]);
    assert_eq!(code, 0);
    assert!(out.contains("lights_point: requires PointLights") && out.contains("refine (refine.wgsl"), "{out}");
    // The passes over a work list say so.
    assert!(out.contains("refine (refine.wgsl:main, then listed over its work list)"), "{out}");
}

#[test]
fn malformed_scene_names_file_and_line() {
    let dir = scratch("cli-scene");
    let scene = write(&dir, "bad.ron", "Scene(\n  camera: Camera(position: (0.0, 0.0, 3.0), target: (0.0, 0.0, 0.0), vfov_deg: 40.0),\n  objects: [ Sphere(center: (0.0, 0.0, 0.0) radius: 1.0, material: \"w\") ],\n)\n");
    let (code, _, err) = glint(&["render", &scene, "--out", "target/x.png"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("bad.ron:3"), "{err}");
    let scene = write(&dir, "nan.ron", "Scene(\n  camera: Camera(position: (0.0, 0.0, 3.0), target: (0.0, 0.0, 0.0), vfov_deg: 40.0),\n  materials: { \"w\": Material(albedo: (0.5, 0.5, 0.5)) },\n  objects: [\n    Sphere(center: (0.0, 0.0, 0.0), radius: NaN, material: \"w\"),\n  ],\n)\n");
    let (code, _, err) = glint(&["render", &scene, "--out", "target/x.png"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("nan.ron:5") && err.contains("radius"), "{err}");
}

#[test]
fn broken_graph_and_shader_name_file_and_line() {
    let dir = scratch("cli-graph");
    std::fs::create_dir_all(dir.join("passes")).unwrap();
    std::fs::create_dir_all(dir.join("shaders/shared")).unwrap();
    for f in std::fs::read_dir(repo().join("shaders/shared")).unwrap() {
        let f = f.unwrap();
        std::fs::copy(f.path(), dir.join("shaders/shared").join(f.file_name())).unwrap();
    }
    // An unknown resource in a graph: the pass's line in the graph file.
    let text = std::fs::read_to_string(repo().join("passes/direct.ron")).unwrap().replace("\"src\": \"lit\"", "\"src\": \"lti\"");
    for f in ["gbuffer.wgsl", "albedo.wgsl", "lights.wgsl", "accumulate.wgsl"] {
        std::fs::copy(repo().join("shaders").join(f), dir.join("shaders").join(f)).unwrap();
    }
    let graph = write(&dir.join("passes"), "g.ron", &text);
    let (code, _, err) = glint(&["graph", "check", &graph]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("g.ron:") && err.contains("lti") && err.contains("accumulate"), "{err}");
    // A WGSL type error: the shader file and line.
    let good = std::fs::read_to_string(repo().join("passes/direct.ron")).unwrap();
    let graph = write(&dir.join("passes"), "g.ron", &good);
    let shader = std::fs::read_to_string(repo().join("shaders/albedo.wgsl")).unwrap().replace("let m = stored_material(", "let m: u32 = stored_material(");
    let line = shader.lines().position(|l| l.contains("let m: u32")).unwrap() + 1;
    write(&dir.join("shaders"), "albedo.wgsl", &shader);
    let (code, _, err) = glint(&["graph", "check", &graph]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(&format!("albedo.wgsl:{line}")), "{err}");
    // RON syntax error in the graph.
    let graph = write(&dir.join("passes"), "g.ron", "FrameGraph(\n  name: \"x\",\n  passes: [,\n)\n");
    let (code, _, err) = glint(&["graph", "check", &graph]);
    assert_eq!(code, 2);
    assert!(err.contains("g.ron:3"), "{err}");
}

#[test]
fn bad_sizes_are_refused() {
    let (code, _, err) = glint(&["render", "scenes/cornell.ron", "--size", "0x64", "--out", "target/x.png"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("empty") || err.contains("0x64"), "{err}");
    let (code, _, err) = glint(&["render", "scenes/cornell.ron", "--size", "abc", "--out", "target/x.png"]);
    assert_eq!(code, 2, "{err}");
    if common::gpu().is_some() {
        let (code, _, err) = glint(&["render", "scenes/cornell.ron", "--size", "100000x64", "--out", "target/x.png"]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains("limit"), "{err}");
    }
}

#[test]
fn missing_obj_is_a_clear_error() {
    let dir = scratch("cli-obj");
    let scene = write(&dir, "obj.ron", "Scene(\n  camera: Camera(position: (0.0, 0.0, 3.0), target: (0.0, 0.0, 0.0), vfov_deg: 40.0),\n  objects: [\n    Mesh(path: \"nowhere.obj\"),\n  ],\n)\n");
    let (code, _, err) = glint(&["render", &scene, "--out", "target/x.png"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("obj.ron:4") && err.contains("nowhere.obj"), "{err}");
}

#[test]
fn graph_edits_from_the_command_line() {
    // Skipping refine leaves the mask passes feeding nothing: culled.
    let (code, out, err) = glint(&["graph", "check", "passes/hybrid.ron", "--scene", "scenes/cornell.ron", "--skip", "refine"]);
    assert_eq!(code, 0, "{err}");
    let culled = out.split("culled:").nth(1).unwrap_or_default();
    for pass in ["sobel", "blur_h", "blur_v", "threshold"] {
        assert!(culled.contains(&format!("{pass}:")), "{pass} not culled:\n{out}");
    }
    assert!(!out.contains("refine (refine.wgsl"), "{out}");
    let (code, out, err) = glint(&["graph", "check", "passes/hybrid.ron", "--set", "accumulate.mode=0"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("accumulate"), "{out}");
    // Bad edits are clear errors, not panics.
    let (code, _, err) = glint(&["graph", "check", "passes/hybrid.ron", "--set", "accumulate.no_such=1"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("no_such"), "{err}");
    let (code, _, err) = glint(&["graph", "check", "passes/hybrid.ron", "--skip", "nope"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("nope") && err.contains("gbuffer"), "{err}");
    let (code, _, err) = glint(&["graph", "check", "passes/hybrid.ron", "--set", "accumulate.mode"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("pass.param=value"), "{err}");
}

/// `glint bake --out` then `glint render --volume`: the loaded volume is
/// the one baked in a render session (bit for bit: the bake's random
/// streams follow the iteration, not the frame), and a volume for another
/// scene or mode is refused with the reason.
#[test]
fn a_baked_volume_loads_and_a_stale_one_is_refused() {
    if common::gpu().is_none() {
        return;
    }
    let dir = scratch("bake");
    let vol = dir.join("cornell.glv").to_string_lossy().into_owned();
    let (code, out, err) = glint(&["bake", "scenes/cornell.ron", "--level", "2", "--spa", "4", "--paths", "32", "--out", &vol]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("(13824 bytes;"), "27 probes x 2 x 4^2 x 16 bytes: {out}");
    let loaded = dir.join("loaded.pfm").to_string_lossy().into_owned();
    let baked = dir.join("baked.pfm").to_string_lossy().into_owned();
    let common_args = ["--graph", "passes/irradiance.ron", "--size", "8x8", "--output", "thesis_irradiance", "--set", "probes.level=2"];
    // The same map size as the bake's --spa 4: a graph variant.
    let graph = std::fs::read_to_string(repo().join("passes/irradiance.ron")).unwrap().replace("ProbeTiles(16, 8)", "ProbeTiles(8, 4)").replace("until: 256", "until: 32");
    let graph_path = write(&dir, "bake-spa4.ron", &graph);
    let with = |extra: &[&str]| {
        let mut a: Vec<&str> = vec!["render", "scenes/cornell.ron"];
        a.extend_from_slice(&common_args);
        a.extend_from_slice(extra);
        a.iter().map(|s| if *s == "passes/irradiance.ron" { graph_path.as_str() } else { s }).map(str::to_string).collect::<Vec<_>>()
    };
    let run = |a: Vec<String>| glint(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let (code, _, err) = run(with(&["--volume", &vol, "--frames", "1", "--out", &loaded]));
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = run(with(&["--frames", "3", "--out", &baked]));
    assert_eq!(code, 0, "{err}");
    assert_eq!(std::fs::read(&loaded).unwrap(), std::fs::read(&baked).unwrap(), "the loaded volume differs from one baked in the session");

    let (code, _, err) = glint(&["render", "scenes/cornell-diffuse.ron", "--graph", "passes/irradiance.ron", "--set", "probes.level=2", "--volume", &vol, "--out", &loaded]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("cornell.glv") && err.contains("geometry, materials or lights changed"), "{err}");
    let (code, _, err) = glint(&["render", "scenes/cornell.ron", "--graph", "passes/irradiance.ron", "--volume", &vol, "--out", &loaded]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("level 2") && err.contains("level 4"), "{err}");
}

/// A small `glint trade`: the files, an error that falls as frames
/// accumulate, and a last FLIP that `glint compare` of the written images
/// agrees with.
#[test]
fn trade_measures_each_graph_against_the_reference() {
    if common::gpu().is_none() {
        return;
    }
    let dir = scratch("trade");
    let out = dir.to_string_lossy().into_owned();
    let args = ["trade", "scenes/cornell.ron", "--graphs", "passes/hybrid-point.ron,passes/pathtrace.ron", "--size", "32x32", "--frames", "8", "--reference-frames", "64", "--out", &out];
    let (code, stdout, err) = glint(&args);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("samples per pixel"), "{stdout}");
    for f in ["trade.csv", "trade.md", "trade.png", "compare.png", "reference.exr", "reference.ron", "hybrid-point-final.exr", "pathtrace-final.exr"] {
        assert!(dir.join(f).is_file(), "{f} missing: {stdout}");
    }
    let csv = std::fs::read_to_string(dir.join("trade.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 16, "{csv}");
    let flip = |graph: &str, frame: &str| -> f64 { rows.iter().find(|r| r[0] == graph && r[2] == frame).map(|r| r[5].parse().unwrap()).unwrap() };
    assert!(flip("pathtrace", "8") < flip("pathtrace", "1"), "the path tracer's error should fall: {csv}");
    let (code, cmp, err) = glint(&["compare", &dir.join("reference.exr").to_string_lossy(), &dir.join("pathtrace-final.exr").to_string_lossy()]);
    assert_eq!(code, 0, "{err}");
    let compared: f64 = cmp.lines().find_map(|l| l.strip_prefix("flip_mean=")).unwrap().parse().unwrap();
    assert!((compared - flip("pathtrace", "8")).abs() < 1e-4, "compare says {compared}, the CSV {}", flip("pathtrace", "8"));
    // A second run finds the reference cached.
    let (code, stdout, err) = glint(&args);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("reference: cached"), "{stdout}");
    // Another graph's reference (direct light only) is not that one: it is
    // rendered, and keyed by its graph.
    let mut direct = args.to_vec();
    direct.extend(["--reference-graph", "passes/direct.ron"]);
    let (code, stdout, err) = glint(&direct);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("stale") && stdout.contains("passes/direct.ron on scenes/cornell.ron"), "{stdout}");
    assert!(std::fs::read_to_string(dir.join("reference.ron")).unwrap().contains("direct.ron"));
}

/// `trade --seeds N`: each frame's row is the mean over seeds 1..N, as
/// `render --seed` and `compare` of each seed give it; trade.md shows the
/// spread.
#[test]
fn trade_over_seeds_averages_what_each_seed_measures() {
    if common::gpu().is_none() {
        return;
    }
    let dir = scratch("trade-seeds");
    let out = dir.to_string_lossy().into_owned();
    // Two graphs: they take turns seed by seed, in reverse order every
    // other seed, and each keeps its own seeds' figures.
    let args = ["trade", "scenes/cornell.ron", "--graphs", "passes/pathtrace.ron,passes/direct.ron", "--size", "32x32", "--frames", "2", "--reference-frames", "32", "--seeds", "3", "--out", &out];
    let (code, stdout, err) = glint(&args);
    assert_eq!(code, 0, "{err}");
    let csv = std::fs::read_to_string(dir.join("trade.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 4, "one row a frame and graph, not one a seed: {csv}");
    let reference = dir.join("reference.exr").to_string_lossy().into_owned();
    for graph in ["pathtrace", "direct"] {
        let mut flips = Vec::new();
        for seed in ["1", "2", "3"] {
            let image = dir.join(format!("{graph}-seed{seed}.exr")).to_string_lossy().into_owned();
            let path = format!("passes/{graph}.ron");
            let (code, _, err) = glint(&["render", "scenes/cornell.ron", "--graph", &path, "--size", "32x32", "--frames", "1", "--seed", seed, "--out", &image]);
            assert_eq!(code, 0, "{err}");
            let (code, cmp, err) = glint(&["compare", &reference, &image]);
            assert_eq!(code, 0, "{err}");
            flips.push(cmp.lines().find_map(|l| l.strip_prefix("flip_mean=")).unwrap().parse::<f64>().unwrap());
        }
        assert!(flips[0] != flips[1] && flips[1] != flips[2], "{graph}: seeds draw different samples: {flips:?}");
        let mean = flips.iter().sum::<f64>() / 3.0;
        let row = rows.iter().find(|r| r[0] == graph && r[2] == "1").unwrap_or_else(|| panic!("no first frame of {graph}: {csv}"));
        let first: f64 = row[5].parse().unwrap();
        assert!((first - mean).abs() < 1e-4, "{graph}: the CSV's first frame {first}, the seeds' mean {mean} ({flips:?})");
    }
    let md = std::fs::read_to_string(dir.join("trade.md")).unwrap();
    assert!(md.contains("Over the seeds") && md.contains("| pathtrace | 3 |") && md.contains("| direct | 3 |"), "{md}\n{stdout}");
    for bad in [&["--seeds", "0"][..], &["--seeds", "2", "--animate"][..]] {
        let mut a = vec!["trade", "scenes/cornell.ron", "--graphs", "passes/pathtrace.ron", "--out", &out];
        a.extend(bad);
        let (code, _, err) = glint(&a);
        assert_ne!(code, 0, "{bad:?} was taken");
        assert!(err.contains("--seeds"), "{err}");
    }
}

#[test]
fn trade_in_motion_compares_every_kth_frame_with_its_own_instant() {
    if common::gpu().is_none() {
        return;
    }
    let dir = scratch("trade-animate");
    let out = dir.to_string_lossy().into_owned();
    let args = [
        "trade", "scenes/moving-lights.ron", "--graphs", "passes/realtime.ron,passes/pathtrace.ron", "--size", "24x24", "--frames", "4",
        "--animate", "--camera-path", "orbit:30", "--reference-every", "2", "--reference-frames", "8", "--out", &out,
    ];
    let (code, stdout, err) = glint(&args);
    assert_eq!(code, 0, "{err}");
    // One reference per compared frame, each of its own instant.
    for f in ["reference-f0002.exr", "reference-f0004.exr", "trade.csv", "trade.md", "trade.png", "realtime-final.exr"] {
        assert!(dir.join(f).is_file(), "{f} missing: {stdout}");
    }
    let key2 = std::fs::read_to_string(dir.join("reference-f0002.ron")).unwrap();
    let key4 = std::fs::read_to_string(dir.join("reference-f0004.ron")).unwrap();
    assert_ne!(key2, key4, "the two instants' references differ in time and camera");
    let csv = std::fs::read_to_string(dir.join("trade.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.iter().map(|r| (r[0], r[2])).collect::<Vec<_>>(), [("realtime", "2"), ("realtime", "4"), ("pathtrace", "2"), ("pathtrace", "4")], "{csv}");
    // Cumulative time counts the frames between compared ones too.
    let cum: f64 = rows[1][4].parse().unwrap();
    let ms: f64 = rows[1][3].parse().unwrap();
    assert!(cum > 2.0 * ms, "{csv}");
    let md = std::fs::read_to_string(dir.join("trade.md")).unwrap();
    assert!(md.contains("## In motion") && md.contains("| realtime |"), "{md}");
    let (code, _, err) = glint(&["trade", "scenes/cornell.ron", "--graphs", "passes/realtime.ron", "--animate", "--reference-every", "9", "--frames", "4", "--out", &out]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--reference-every 9"), "{err}");
    let (code, _, err) = glint(&["trade", "scenes/cornell.ron", "--graphs", "passes/realtime.ron", "--animate", "--reference", "x.exr", "--frames", "4", "--out", &out]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--reference with --animate"), "{err}");
}

#[test]
fn trade_sweeps_settings_and_skips_the_ones_a_graph_cannot_take() {
    if common::gpu().is_none() {
        return;
    }
    let dir = scratch("trade-sweep");
    let sweep = write(
        &dir,
        "sweep.ron",
        r#"Sweep(settings: [
            (name: "half", resolution_scale: 0.5),
            (name: "generic", specialise: false, cull: false),
            (name: "8 spp", params: { "pathtrace.spp": 8 }),
        ])"#,
    );
    let out = dir.join("out").to_string_lossy().into_owned();
    let args = ["trade", "scenes/cornell-point.ron", "--graphs", "passes/hybrid-point.ron,passes/pathtrace.ron", "--sweep", &sweep, "--size", "32x32", "--frames", "4", "--reference-frames", "16", "--out", &out];
    let (code, stdout, err) = glint(&args);
    assert_eq!(code, 0, "{err}");
    // hybrid-point has no pathtrace pass: its `8 spp` is skipped, said so.
    assert!(stdout.contains("hybrid-point.ron [8 spp]: skipped, the graph has no pass `pathtrace`"), "{stdout}");
    let csv = std::fs::read_to_string(dir.join("out/trade.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 5 * 4, "{csv}");
    for (graph, setting) in [("hybrid-point", "half"), ("hybrid-point", "generic"), ("pathtrace", "half"), ("pathtrace", "generic"), ("pathtrace", "8 spp")] {
        assert_eq!(rows.iter().filter(|r| r[0] == graph && r[1] == setting).count(), 4, "{graph} [{setting}]: {csv}");
    }
    assert!(dir.join("out/pathtrace-8_spp-final.exr").is_file());
    let flip = |setting: &str| -> f64 { rows.iter().find(|r| r[0] == "pathtrace" && r[1] == setting && r[2] == "4").map(|r| r[5].parse().unwrap()).unwrap() };
    // 8 samples a frame beat 1.
    assert!(flip("8 spp") < flip("generic"), "{csv}");
    // A broken sweep names its file and line.
    let bad = write(&dir, "bad.ron", "Sweep(settings: [\n  (name: \"a\", sclae: 2.0),\n])");
    let (code, _, err) = glint(&["trade", "scenes/cornell.ron", "--graphs", "passes/pathtrace.ron", "--sweep", &bad, "--out", &out]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("bad.ron:2"), "{err}");
}

#[test]
fn bench_thesis_writes_its_report() {
    if common::gpu().is_none() {
        return;
    }
    let dir = scratch("thesis");
    let out = dir.to_string_lossy().into_owned();
    // A target no frame can meet, and a cap the first copy passes.
    let args = ["bench", "thesis", "--size", "16x16", "--frames", "3", "--reference-frames", "8", "--stress-target-ms", "0.001", "--stress-max-triangles", "200", "--out", &out];
    let (code, stdout, err) = glint(&args);
    assert_eq!(code, 0, "{err}");
    let md = std::fs::read_to_string(dir.join("thesis.md")).unwrap_or_else(|e| panic!("{e}: {stdout}"));
    for section in ["Adapter: **", "## Table 4.1", "## Convergence speed-up", "## Post-processing", "## Light scaling", "## Stress test"] {
        assert!(md.contains(section), "{section} missing:\n{md}");
    }
    // Three environments with their speed-ups for both hybrids and the
    // real-time graph, and the light counts multiplied (3 x env3's one
    // light; 1, 2, 4 in the stress scene).
    for row in ["| 1 | hybrid |", "| 3 | hybrid-gi |", "| 2 | realtime |", "| thesis-env3.ron | 3 |", "| thesis-stress.ron | 4 |"] {
        assert!(md.contains(row), "{row} missing:\n{md}");
    }
    assert!(md.contains("longer than 0.001 ms a frame at every count"), "{md}");
    assert!(md.contains("| 1 | 220 |"), "the stress test's second step: {md}");
}

/// `bench rays --trips` counts each primary ray's BLAS trips on the GPU:
/// a ray through a screen tile whose frustum misses the mesh takes none (its
/// tile has no entries: src/bvh/tiles.rs), a view of the mesh also tests
/// triangles, and without the flag nothing is counted.
#[test]
fn bench_rays_counts_traversal_trips() {
    let trips = |camera: &str, flag: bool| {
        let mut args = vec!["bench", "rays", "--obj", "scenes/meshes/knot.obj", "--size", "32x16", "--camera", camera, "--runs", "1"];
        if flag {
            args.push("--trips");
        }
        let (code, out, err) = glint(&args);
        assert_eq!(code, 0, "{err}");
        let value = |key: &str| out.lines().find_map(|l| l.strip_prefix(&format!("{key}="))).map(|v| v.parse::<f64>().unwrap_or(f64::NAN));
        (value("trips_node_per_ray"), value("trips_triangle_per_ray"), value("trips_per_ray"), value("trips_group_max_per_ray"))
    };
    // Looking away: no tile sees the mesh.
    assert_eq!(trips("0,0,5,0,0,10,45", true), (Some(0.0), Some(0.0), Some(0.0), Some(0.0)));
    let (node, tri, all, group) = trips("0,0,5,0,0,0,45", true);
    let (node, tri, all, group) = (node.unwrap(), tri.unwrap(), all.unwrap(), group.unwrap());
    assert!(node > 1.0 && tri > 0.0, "node {node}, triangle {tri}");
    assert!((node + tri - all).abs() < 2e-3 && group >= all, "per ray {all}, busiest lane {group}");
    assert_eq!(trips("0,0,5,0,0,0,45", false), (None, None, None, None));
    // Every pass is timed, the query pass too (no output reads it: the
    // bench keeps it with `also_compute`).
    let (code, out, err) = glint(&["bench", "rays", "--obj", "scenes/meshes/knot.obj", "--size", "32x16", "--camera", "0,0,5,0,0,0,45", "--runs", "1"]);
    assert_eq!(code, 0, "{err}");
    for pass in ["query", "primary", "shadow", "diffuse"] {
        assert!(out.lines().any(|l| l.starts_with(&format!("{pass}_ms_wall="))), "no {pass}_ms_wall in:\n{out}");
    }
    // A one-mesh scene takes a tile table: what building it costs is timed.
    let table = out.lines().find_map(|l| l.strip_prefix("tile_table_ms=")).and_then(|v| v.parse::<f64>().ok());
    assert!(table.is_some_and(|ms| ms.is_finite() && ms >= 0.0), "no tile_table_ms in:\n{out}");
}

/// `--vs DIR` times another checkout's bench graph in the same process,
/// run by run in turn, and prints its times and the per-run ratios; a
/// folder without a bench graph is an error that names the file.
#[test]
fn bench_rays_times_another_checkout_in_turn() {
    let base = ["bench", "rays", "--obj", "scenes/meshes/knot.obj", "--size", "32x16", "--camera", "0,0,5,0,0,0,45", "--runs", "2", "--vs"];
    let (code, out, err) = glint(&[&base[..], &["."]].concat());
    assert_eq!(code, 0, "{err}");
    for pass in ["query", "primary", "shadow", "diffuse"] {
        for key in [format!("vs_{pass}_ms_wall="), format!("vs_{pass}_ms_wall_min="), format!("{pass}_over_vs=")] {
            assert!(out.lines().any(|l| l.starts_with(&key)), "no {key} in:\n{out}");
        }
    }
    let (code, _, err) = glint(&[&base[..], &["scenes"]].concat());
    assert_ne!(code, 0);
    assert!(err.contains("bench-rays.ron"), "{err}");
}

/// `bench frames` renders two graphs in turn and prints the median
/// per-frame ratio, and with `--profile` each pass's.
#[test]
fn bench_frames_compares_two_graphs_in_turn() {
    let (code, out, err) = glint(&["bench", "frames", "scenes/cornell.ron", "--graph", "passes/hybrid-point.ron", "--vs", "passes/hybrid-point.ron", "--size", "32x16", "--frames", "2", "--profile"]);
    assert_eq!(code, 0, "{err}");
    for key in ["frame_over_vs=", "gbuffer_over_vs=", "accumulate_over_vs="] {
        assert!(out.contains(key), "no {key} in:\n{out}");
    }
    let (code, _, err) = glint(&["bench", "frames", "scenes/cornell.ron", "--graph", "passes/hybrid-point.ron", "--vs", "passes/none.ron", "--frames", "1"]);
    assert_ne!(code, 0);
    assert!(err.contains("none.ron"), "{err}");
}
