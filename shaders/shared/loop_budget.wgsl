// lavapipe ends every loop of an invocation once 65535 iterations have
// run in all (one count shared by every loop of a SIMD group's run of the
// shader; src/graph/compile/split.rs). A shader that traces one ray per
// invocation never comes near it; one that traces many in turn (a tile
// pool's invocations, shared/tile_pool.wgsl) must stop taking work before
// it does. The traversal loops count their trips here, each lane its own.
// A SIMD group's trips at a step are its busiest lane's, so they never
// exceed the sum of its lanes' counts.
var<private> loop_trips: u32;
