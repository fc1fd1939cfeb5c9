//! What a shader may ask of each invocation's memory. naga validates a
//! `var<private> array<vec4f, 100000>` (1.5 MiB per invocation), and then
//! the driver spends minutes compiling it (lavapipe: over 60 s); a
//! workgroup array beyond the adapter's limit fails only at pipeline
//! creation. Both are refused here, at the declaration, with the figures.

use naga::proc::Layouter;
use naga::AddressSpace;

use super::ShaderSource;
use crate::error::UserError;

/// Private globals plus every function's local variables (an upper bound on
/// what one invocation keeps: functions may be inlined into each other).
/// The shipped shaders use under 2 KiB.
pub const MAX_PRIVATE_BYTES: u64 = 64 * 1024;
/// wgpu's default `max_compute_workgroup_storage_size`, which every adapter
/// glint runs on offers.
pub const MAX_WORKGROUP_BYTES: u64 = 16 * 1024;

/// Refuses a shader whose private and function variables are over
/// [`MAX_PRIVATE_BYTES`] (at the biggest of them) or whose workgroup
/// variables are over [`MAX_WORKGROUP_BYTES`] (at the one that crosses it).
pub fn check(source: &ShaderSource, module: &naga::Module) -> Result<(), UserError> {
    let mut layouter = Layouter::default();
    // A type the layouter cannot size has already failed validation.
    if layouter.update(module.to_ctx()).is_err() {
        return Ok(());
    }
    let size = |ty: naga::Handle<naga::Type>| u64::from(layouter[ty].size);
    let mut private = 0u64;
    let mut workgroup = 0u64;
    let mut biggest: Option<(u64, naga::Span, String)> = None;
    let mut note = |bytes: u64, span: naga::Span, what: String| {
        if biggest.as_ref().is_none_or(|b| bytes > b.0) {
            biggest = Some((bytes, span, what));
        }
    };
    for (handle, var) in module.global_variables.iter() {
        let bytes = size(var.ty);
        let name = var.name.clone().unwrap_or_default();
        match var.space {
            AddressSpace::Private => {
                private += bytes;
                note(bytes, module.global_variables.get_span(handle), format!("`var<private> {name}`"));
            }
            AddressSpace::WorkGroup => {
                workgroup += bytes;
                if workgroup > MAX_WORKGROUP_BYTES {
                    return Err(UserError::at(
                        source.span_location(module.global_variables.get_span(handle)),
                        format!("`var<workgroup> {name}` brings the workgroup memory to {} bytes; adapters are only required to offer {MAX_WORKGROUP_BYTES}", workgroup),
                    ));
                }
            }
            _ => {}
        }
    }
    let functions = module.functions.iter().map(|(_, f)| f).chain(module.entry_points.iter().map(|e| &e.function));
    for f in functions {
        for (handle, local) in f.local_variables.iter() {
            let bytes = size(local.ty);
            private += bytes;
            let name = local.name.clone().unwrap_or_default();
            note(bytes, f.local_variables.get_span(handle), format!("`var {name}` in `{}`", f.name.clone().unwrap_or_default()));
        }
    }
    if private > MAX_PRIVATE_BYTES {
        let (bytes, span, what) = biggest.unwrap_or((0, naga::Span::UNDEFINED, String::new()));
        return Err(UserError::at(
            source.span_location(span),
            format!(
                "{what} takes {bytes} bytes per invocation, {private} in all with the shader's other private and function variables; glint allows {MAX_PRIVATE_BYTES} (drivers take minutes to compile more, and spill it to slow memory)"
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::shader::source::expand_text;

    fn compile(text: &str) -> Result<(), String> {
        let src = expand_text(text, Path::new("big.wgsl"), Path::new(env!("CARGO_MANIFEST_DIR"))).map_err(|e| e.to_string())?;
        crate::shader::from_source(src).map(|_| ()).map_err(|e| e.to_string())
    }

    const MAIN: &str = "@compute @workgroup_size(8, 8)\nfn main(@builtin(global_invocation_id) id: vec3u) {\n    touch(id.x);\n}\n";

    #[test]
    fn huge_private_and_workgroup_arrays_are_refused_at_their_line() {
        let private = format!("var<private> big: array<vec4f, 100000>;\nfn touch(i: u32) {{ big[i] = vec4f(1.0); }}\n{MAIN}");
        let e = compile(&private).unwrap_err();
        assert!(e.starts_with("big.wgsl:1:") && e.contains("`var<private> big` takes 1600000 bytes"), "{e}");
        let local = format!("fn touch(i: u32) {{\n    var a: array<f32, 20000>;\n    a[i] = 1.0;\n}}\n{MAIN}");
        let e = compile(&local).unwrap_err();
        assert!(e.starts_with("big.wgsl:2:") && e.contains("`var a` in `touch` takes 80000 bytes"), "{e}");
        let shared = format!("var<workgroup> tile: array<vec4f, 2048>;\nfn touch(i: u32) {{ tile[i] = vec4f(1.0); }}\n{MAIN}");
        let e = compile(&shared).unwrap_err();
        assert!(e.starts_with("big.wgsl:1:") && e.contains("32768 bytes"), "{e}");
        // What the engine's own shaders need passes.
        let fine = format!("var<private> stack: array<u32, 64>;\nfn touch(i: u32) {{ stack[i & 63u] = i; }}\n{MAIN}");
        compile(&fine).unwrap();
    }
}
