// The `run` uniform of a pass that does not run once a frame
// (src/graph/runs.rs): which dispatch this is. A pass binds it by
// importing this file; the engine writes it before each dispatch.

struct Run {
    // Dispatches of this pass since the graph was built or restarted.
    iteration: u32,
    // Dispatches since the scene last changed (0: the first after a change,
    // where a progressive pass starts over).
    since_change: u32,
    // This dispatch's index within the frame, and the frame's count.
    index: u32,
    count: u32,
}

@group(2) @binding(0) var<uniform> run: Run;
