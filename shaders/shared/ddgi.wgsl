// DDGI's probe tiles (Majercik et al., JCGT 2019 and 2021): each probe has
// an octahedral irradiance map and a map of mean distance and mean squared
// distance, each an n x n interior inside a one-texel border that repeats
// the map's own texels across the octahedron's folds, so bilinear lookups
// never leave a tile. Tile sizes come from the atlases' dimensions.
#import probes

const GOLDEN_ANGLE: f32 = 2.39996322972865;

// Ray `i` of `count` in spherical-Fibonacci directions (evenly spread).
fn fibonacci_dir(i: u32, count: u32) -> vec3f {
    let z = 1.0 - (2.0 * f32(i) + 1.0) / f32(count);
    let r = sqrt(max(0.0, 1.0 - z * z));
    let phi = f32(i) * GOLDEN_ANGLE;
    return vec3f(r * cos(phi), r * sin(phi), z);
}

// A uniformly random rotation from three uniform numbers (a unit
// quaternion, Shoemake), as a matrix.
fn random_rotation(u: vec3f) -> mat3x3f {
    let a = sqrt(1.0 - u.x);
    let b = sqrt(u.x);
    let t1 = 2.0 * PROBE_PI * u.y;
    let t2 = 2.0 * PROBE_PI * u.z;
    let q = vec4f(a * sin(t1), a * cos(t1), b * sin(t2), b * cos(t2));
    let x = q.x;
    let y = q.y;
    let z = q.z;
    let w = q.w;
    return mat3x3f(
        vec3f(1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + w * z), 2.0 * (x * z - w * y)),
        vec3f(2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + w * x)),
        vec3f(2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y)),
    );
}

// The interior texel a texel of a tile (interior n, tile n + 2) holds:
// itself inside, its mirror across the fold on the border.
fn border_source(t: vec2u, n: u32) -> vec2u {
    let last = n + 1u;
    let x_in = t.x >= 1u && t.x <= n;
    let y_in = t.y >= 1u && t.y <= n;
    if x_in && y_in {
        return t;
    }
    if x_in {
        return vec2u(last - t.x, select(n, 1u, t.y == 0u));
    }
    if y_in {
        return vec2u(select(n, 1u, t.x == 0u), last - t.y);
    }
    // Corners: the opposite interior corner.
    return vec2u(select(1u, n, t.x == 0u), select(1u, n, t.y == 0u));
}

// The direction at the centre of interior texel t (1..=n in each axis).
fn oct_texel_dir(t: vec2u, n: u32) -> vec3f {
    let e = (vec2f(t - vec2u(1u)) + 0.5) / f32(n) * 2.0 - 1.0;
    return oct_decode(e);
}

// Where direction d falls in a tile, in texels from the tile's corner
// (continuous: texel (i, j) spans [i, i+1) x [j, j+1)).
fn oct_tile_point(d: vec3f, n: u32) -> vec2f {
    return (oct_encode(d) + 1.0) * 0.5 * f32(n) + 1.0;
}

// The largest distance a probe's distance map records: a ray that misses
// (or goes farther) counts as this far. Beyond a cell and a half nothing
// is shaded from this probe.
fn ddgi_max_distance() -> f32 {
    return 1.5 * length(frame.probe_spacing);
}
