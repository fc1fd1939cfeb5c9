// A pass's texels taken from a pool, a chunk at a time, instead of fixed
// by each invocation's id: persistent threads (Aila and Laine 2009), so
// the device's threads share out the image as they go.
//
// Why: lavapipe hands each of its threads an equal, contiguous share of a
// dispatch's workgroups before any runs (its compute thread pool), so
// with a fixed texel per invocation one thread draws the top half of the
// image and the other the bottom half. Where one half costs more, or
// where another tenant slows one core, the other thread finishes early
// and waits. Taking chunks from one counter, a thread that runs faster
// takes more of them.
//
// The engine zeroes `tile_pool` before the pass and dispatches fewer
// invocations than texels (src/graph/tile_pool.rs): on a CPU, up to
// POOL_CHUNKS chunks each and a quarter more invocations than that needs;
// then a second, indirect dispatch of the same entry over any chunks the
// first left (a lane stops taking chunks near lavapipe's loop budget,
// shared/loop_budget.wgsl). Each invocation loops
//
//     var cursor = PoolCursor();
//     loop {
//         let id = pool_next(&cursor);
//         if id.z != 0u { break; }
//         if in_frame(id) { ... texel id.xy ... }
//     }
//
// Every texel of frame.size comes out exactly once, in whichever
// invocation takes its chunk; a pass's image is the same whatever order.
// Each ray traced there can loop at least 4095 times before lavapipe's
// budget ends it (a ray an invocation traces alone: 65535).
#import frame
#import loop_budget

@group(2) @binding(2) var<storage, read_write> tile_pool: atomic<u32>;

// Lanes whose chunks lie side by side: lane l of a strip takes columns l,
// l + POOL_LANES, ... of it. 8 is lavapipe's SIMD width, so the lanes of a
// SIMD group, which take their chunks in turn, trace neighbouring texels
// of one row together, as a workgroup of 64 x 1 did. Any width is correct.
// (Mirrors LANES in src/graph/tile_pool.rs.)
const POOL_LANES: u32 = 8u;
// Texels per chunk, one per trip of the caller's loop (mirrors STEPS).
const POOL_STEPS: u32 = 8u;
// A strip: the texels of POOL_LANES chunks, along one row.
const POOL_STRIP: u32 = POOL_LANES * POOL_STEPS;

// Chunks an invocation takes at most: set by the engine per device
// (src/graph/tile_pool.rs), many on a CPU, where an invocation that
// takes more is how one thread does more than its share.
override POOL_CHUNKS: u32 = 1u;
// A lane takes no chunk once its traversals have looped this often
// (shared/loop_budget.wgsl): its SIMD group has then run fewer than
// 8 x 4096 = 32768 trips, which leaves the chunk in hand 32767 more:
// 4095 for each of its 8 texels' rays. (One ray an invocation had 65535.)
const POOL_TRIP_BUDGET: u32 = 4096u;

// Where an invocation is in its chunk. The zero value has none yet.
struct PoolCursor {
    x: u32,
    y: u32,
    // Texels of the chunk still to hand out.
    left: u32,
    // Chunks taken.
    taken: u32,
}

// The invocation's next texel as (x, y, 0), or z = 1 once the pool is
// empty. A texel past the right edge (the last strip of a row) comes out
// too: the caller skips it with in_frame and goes on.
fn pool_next(cursor: ptr<function, PoolCursor>) -> vec3u {
    if (*cursor).left == 0u {
        if (*cursor).taken >= POOL_CHUNKS || loop_trips >= POOL_TRIP_BUDGET {
            return vec3u(0u, 0u, 1u);
        }
        (*cursor).taken += 1u;
        let chunk = atomicAdd(&tile_pool, 1u);
        let strip = chunk / POOL_LANES;
        let per_row = (frame.size.x + POOL_STRIP - 1u) / POOL_STRIP;
        let row = strip / per_row;
        (*cursor).x = (strip - row * per_row) * POOL_STRIP + (chunk - strip * POOL_LANES);
        (*cursor).y = row;
        (*cursor).left = POOL_STEPS;
    }
    let id = vec3u((*cursor).x, (*cursor).y, select(0u, 1u, (*cursor).y >= frame.size.y));
    (*cursor).x += POOL_LANES;
    (*cursor).left -= 1u;
    return id;
}
