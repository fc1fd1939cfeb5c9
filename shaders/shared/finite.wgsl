// Whether every component is finite, by bits (exponent not all ones): a
// shader compiler may assume `v == v` always holds and fold a NaN test
// away (mirrored by `mean::all_finite` in src/mean.rs).
fn all_finite(v: vec3f) -> bool {
    let e = bitcast<vec3u>(v) & vec3u(0x7f800000u);
    return all(e != vec3u(0x7f800000u));
}
