// The probe grid of the frame uniform and the direction maps of probe
// tiles. Mirrors src/probes/grid.rs and src/probes/mapping.rs (tested
// against them in tests/probes_gpu.rs).
#import frame

const PROBE_PI: f32 = 3.14159265358979;
const PROBE_FRAC_PI_4: f32 = 0.78539816339745;

// Probe (i, j, k)'s linear index (x fastest) and its tile in an atlas of
// `ProbeTiles` (probe p at tile (p mod n^2, p / n^2)).
fn probe_index(p: vec3u) -> u32 {
    let n = frame.probe_n;
    return p.x + n * (p.y + n * p.z);
}

fn probe_tile(index: u32) -> vec2u {
    let nn = frame.probe_n * frame.probe_n;
    return vec2u(index % nn, index / nn);
}

fn probe_position(p: vec3u) -> vec3f {
    return frame.probe_origin + frame.probe_spacing * vec3f(p);
}

// Probe (i, j, k) of a linear index.
fn probe_coords(index: u32) -> vec3u {
    let n = frame.probe_n;
    return vec3u(index % n, (index / n) % n, index / (n * n));
}

struct ProbeCell {
    // The cell's lowest probe (every component at most n - 2).
    base: vec3u,
    // The position within the cell, in [0, 1]^3.
    f: vec3f,
}

// The cell of `x`, clamped to the grid (outside: the nearest cell, leaning
// on its face); a NaN component counts as 0 (tested by bits: a compiler
// may fold `x != x` away).
fn probe_cell(x: vec3f) -> ProbeCell {
    var g = (x - frame.probe_origin) / frame.probe_spacing;
    let nan = (bitcast<vec3u>(g) & vec3u(0x7fffffffu)) > vec3u(0x7f800000u);
    g = select(g, vec3f(0.0), nan);
    let last = vec3f(f32(frame.probe_n) - 2.0);
    g = clamp(g, vec3f(0.0), last + 1.0);
    let base = min(floor(g), last);
    return ProbeCell(vec3u(base), clamp(g - base, vec3f(0.0), vec3f(1.0)));
}

// Corner c (0..8: bit 0 x, bit 1 y, bit 2 z) of a cell: its probe and
// trilinear weight.
fn cell_corner(cell: ProbeCell, c: u32) -> vec3u {
    return cell.base + vec3u(c & 1u, (c >> 1u) & 1u, (c >> 2u) & 1u);
}

fn corner_weight(cell: ProbeCell, c: u32) -> f32 {
    let bits = vec3u(c & 1u, (c >> 1u) & 1u, (c >> 2u) & 1u) == vec3u(1u);
    let w = select(1.0 - cell.f, cell.f, bits);
    return w.x * w.y * w.z;
}

// Shirley-Chiu: the square [-1, 1]^2 onto the unit disk.
fn square_to_disk(p: vec2f) -> vec2f {
    let a = p.x;
    let b = p.y;
    if a == 0.0 && b == 0.0 {
        return vec2f(0.0);
    }
    var r: f32;
    var phi: f32;
    if abs(a) > abs(b) {
        r = a;
        phi = PROBE_FRAC_PI_4 * (b / a);
    } else {
        r = b;
        phi = 2.0 * PROBE_FRAC_PI_4 - PROBE_FRAC_PI_4 * (a / b);
    }
    return vec2f(r * cos(phi), r * sin(phi));
}

fn disk_to_square(d: vec2f) -> vec2f {
    let r = length(d);
    if r == 0.0 {
        return vec2f(0.0);
    }
    var phi = atan2(d.y, d.x);
    if phi < -PROBE_FRAC_PI_4 {
        phi += 2.0 * PROBE_PI;
    }
    if phi < PROBE_FRAC_PI_4 {
        return vec2f(r, phi * r / PROBE_FRAC_PI_4);
    } else if phi < 3.0 * PROBE_FRAC_PI_4 {
        return vec2f(-(phi - 2.0 * PROBE_FRAC_PI_4) * r / PROBE_FRAC_PI_4, r);
    } else if phi < 5.0 * PROBE_FRAC_PI_4 {
        return vec2f(-r, -(phi - PROBE_PI) * r / PROBE_FRAC_PI_4);
    }
    return vec2f((phi - 6.0 * PROBE_FRAC_PI_4) * r / PROBE_FRAC_PI_4, -r);
}

// [0, 1]^2 onto the hemisphere z >= 0 with equal area.
fn square_to_hemisphere(u: vec2f) -> vec3f {
    let d = square_to_disk(u * 2.0 - 1.0);
    let r2 = min(dot(d, d), 1.0);
    let s = sqrt(2.0 - r2);
    return normalize(vec3f(d * s, 1.0 - r2));
}

// The inverse, for z >= 0 (|z| is used below the horizon).
fn hemisphere_to_square(d: vec3f) -> vec2f {
    let r2 = clamp(1.0 - abs(d.z), 0.0, 1.0);
    let s = sqrt(2.0 - r2);
    var disk = d.xy / s;
    let len = length(disk);
    if len > 0.0 {
        disk *= sqrt(r2) / len;
    }
    return (disk_to_square(disk) + 1.0) * 0.5;
}

// Direction `d`'s texel in a probe's tile of two S x S hemisphere maps
// side by side (z >= 0 left, z < 0 right).
fn hemisphere_texel(d: vec3f, s: u32) -> vec2u {
    let u = hemisphere_to_square(d);
    let cell = min(vec2u(u * f32(s)), vec2u(s - 1u));
    return cell + vec2u(select(s, 0u, d.z >= 0.0), 0u);
}

// A direction within texel `t` of the two-map tile at offset `u` in [0,1)^2
// (u = 0.5: the bucket's centre).
fn hemisphere_texel_dir(t: vec2u, s: u32, u: vec2f) -> vec3f {
    let upper = t.x < s;
    let d = square_to_hemisphere((vec2f(f32(t.x % s), f32(t.y)) + u) / f32(s));
    return select(vec3f(d.xy, -d.z), d, upper);
}

fn sign_not_zero(v: vec2f) -> vec2f {
    return select(vec2f(-1.0), vec2f(1.0), v >= vec2f(0.0));
}

// A unit direction onto the octahedral square [-1, 1]^2, and back.
fn oct_encode(d: vec3f) -> vec2f {
    let p = d.xy / (abs(d.x) + abs(d.y) + abs(d.z));
    if d.z < 0.0 {
        return (1.0 - abs(p.yx)) * sign_not_zero(p);
    }
    return p;
}

fn oct_decode(e: vec2f) -> vec3f {
    var v = vec3f(e, 1.0 - abs(e.x) - abs(e.y));
    if v.z < 0.0 {
        v = vec3f((1.0 - abs(v.yx)) * sign_not_zero(v.xy), v.z);
    }
    return normalize(v);
}
