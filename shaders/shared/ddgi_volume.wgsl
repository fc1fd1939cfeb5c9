// Reading the DDGI volume (shared by the shading pass and the probe rays,
// which sample the previous volume at their hits for more bounces):
// trilinear over the 8 probes of the point's cell, each weighted by a
// smooth backface term and Chebyshev visibility from its distance map, so
// light does not leak through walls; inactive probes (inside geometry)
// count nothing. Bindings in group 3, read-only.
#import ddgi

@group(3) @binding(0) var ddgi_irradiance: texture_storage_2d<rgba32float, read>;
@group(3) @binding(1) var ddgi_distance: texture_storage_2d<rgba32float, read>;
// Per probe: its offset from the grid point (relocation) and 1 if active.
@group(3) @binding(2) var ddgi_state: texture_storage_2d<rgba32float, read>;

// Interior size of a tile of an atlas.
fn tile_interior(atlas: vec2u) -> u32 {
    return atlas.y / max(frame.probe_n, 1u) - 2u;
}

fn probe_state(probe: u32) -> vec4f {
    return textureLoad(ddgi_state, probe_tile(probe));
}

// Bilinear within a probe's tile (Rgba32Float is not filterable, so by
// hand) at continuous tile point `q`: the four texels and the weights.
struct Bilinear {
    i: vec2u,
    f: vec2f,
}

fn tile_bilinear(probe: u32, q: vec2f, n: u32) -> Bilinear {
    let p = vec2f(probe_tile(probe) * (n + 2u)) + q - 0.5;
    return Bilinear(vec2u(floor(p)), p - floor(p));
}

fn irradiance_bilinear(probe: u32, q: vec2f, n: u32) -> vec3f {
    let b = tile_bilinear(probe, q, n);
    let t00 = textureLoad(ddgi_irradiance, b.i).rgb;
    let t10 = textureLoad(ddgi_irradiance, b.i + vec2u(1u, 0u)).rgb;
    let t01 = textureLoad(ddgi_irradiance, b.i + vec2u(0u, 1u)).rgb;
    let t11 = textureLoad(ddgi_irradiance, b.i + vec2u(1u, 1u)).rgb;
    return mix(mix(t00, t10, b.f.x), mix(t01, t11, b.f.x), b.f.y);
}

fn distance_bilinear(probe: u32, q: vec2f, n: u32) -> vec2f {
    let b = tile_bilinear(probe, q, n);
    let t00 = textureLoad(ddgi_distance, b.i).rg;
    let t10 = textureLoad(ddgi_distance, b.i + vec2u(1u, 0u)).rg;
    let t01 = textureLoad(ddgi_distance, b.i + vec2u(0u, 1u)).rg;
    let t11 = textureLoad(ddgi_distance, b.i + vec2u(1u, 1u)).rg;
    return mix(mix(t00, t10, b.f.x), mix(t01, t11, b.f.x), b.f.y);
}

// The irradiance at point `p` with normal `n`, seen from direction `wo`
// (unit, towards the viewer). Bias: the lookup point moves off the surface
// along the normal and towards the viewer by a fraction of the probe
// spacing, so a surface does not shadow itself in the distance maps.
fn ddgi_irradiance_at(p: vec3f, n: vec3f, wo: vec3f) -> vec3f {
    if frame.probe_n < 2u {
        return vec3f(0.0);
    }
    let irr_n = tile_interior(textureDimensions(ddgi_irradiance));
    let dist_n = tile_interior(textureDimensions(ddgi_distance));
    let spacing = min(frame.probe_spacing.x, min(frame.probe_spacing.y, frame.probe_spacing.z));
    let biased = p + (0.2 * n + 0.8 * wo) * (0.3 * spacing);
    let cell = probe_cell(biased);
    var sum = vec3f(0.0);
    var weights = 0.0;
    let q_irr = oct_tile_point(n, irr_n);
    for (var c = 0u; c < 8u; c++) {
        let probe = probe_index(cell_corner(cell, c));
        let state = probe_state(probe);
        if state.w < 0.5 {
            continue;
        }
        let probe_p = probe_position(cell_corner(cell, c)) + state.xyz;
        // Smooth backface: probes behind the surface count little.
        let to_probe = normalize(probe_p - p);
        let facing = (dot(to_probe, n) + 1.0) * 0.5;
        var w = facing * facing + 0.2;
        // Chebyshev: how likely the probe sees the biased point.
        let offset = biased - probe_p;
        let r = length(offset);
        let moments = distance_bilinear(probe, oct_tile_point(offset / max(r, 1e-6), dist_n), dist_n);
        if r > moments.x {
            let variance = abs(moments.y - moments.x * moments.x);
            let gap = r - moments.x;
            let cheb = variance / (variance + gap * gap);
            w *= max(cheb * cheb * cheb, 0.0);
        }
        w = max(w, 1e-6);
        // Crush tiny weights (a probe that barely sees the point).
        if w < 0.2 {
            w *= w * w / 0.04;
        }
        w *= corner_weight(cell, c);
        sum += w * irradiance_bilinear(probe, q_irr, irr_n);
        weights += w;
    }
    if weights <= 0.0 {
        return vec3f(0.0);
    }
    return sum / weights;
}
