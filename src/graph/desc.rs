//! The RON schema of a frame graph (docs/frame-graph.md). A graph file knows
//! nothing about wgpu: resources, passes and the output.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;

use crate::error::{ron_error, UserError};
pub use crate::format::TexFormat;
use crate::scene::Feature;

/// A frame graph file as parsed (`FrameGraph::load`); `compile` turns it into a `Schedule`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameGraph {
    /// The graph's name, for messages and reports.
    pub name: String,
    /// Texture resources, by name (the engine's own are bound by name without being declared).
    #[serde(default)]
    pub resources: BTreeMap<String, ResourceDesc>,
    /// The passes, in file order (which the schedule keeps where dependencies allow).
    pub passes: Vec<PassDesc>,
    /// The resource whose final version the graph renders.
    pub output: String,
    /// The irradiance-volume probe grid, for graphs with probe passes
    /// (sizes `ProbeTiles`, the `frame` uniform's probe fields).
    #[serde(default)]
    pub probes: Option<ProbesDesc>,
    /// WGSL `override` constants for every pass whose shader declares one,
    /// by name (a pass's own `constants` win): what passes must agree on
    /// is set once (realtime.ron: the paths the path and gradient passes
    /// trace, the texel layout the path pass stores and `temporal` reads).
    #[serde(default, deserialize_with = "named_map")]
    pub constants: BTreeMap<String, f64>,
}

/// Which irradiance volume a graph builds: chapter 3's hemisphere maps or
/// DDGI's octahedral maps. Passes pick theirs with `requires: [ThesisProbes]`
/// or `requires: [DdgiProbes]`; the other mode's passes are culled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
pub enum ProbeMode {
    /// Chapter 3's hemisphere maps.
    Thesis,
    /// DDGI's octahedral maps.
    Ddgi,
}

/// `probes: (mode: Thesis, level: 7, padding: 0.1)`: (level+1)^3 probes over
/// the scene's bounds minus `padding` times the extent on each side.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProbesDesc {
    /// Which kind of volume.
    pub mode: ProbeMode,
    /// L: (L+1)^3 probes, 1 to `MAX_PROBE_LEVEL` (7 when omitted).
    #[serde(default = "default_level")]
    pub level: u32,
    /// Fraction of the scene's extent left out on each side, in [0, 0.5) (0.1 when omitted).
    #[serde(default = "default_padding")]
    pub padding: f32,
}

fn default_level() -> u32 {
    7
}

fn default_padding() -> f32 {
    0.1
}

/// The largest probe level: (L+1)^2 tiles side by side must fit a texture.
pub const MAX_PROBE_LEVEL: u32 = 15;

impl ProbesDesc {
    /// Probes per axis.
    pub fn per_axis(&self) -> u32 {
        self.level + 1
    }
}

/// A graph resource (`resources:` in a graph).
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub enum ResourceDesc {
    /// A texture.
    Texture(TextureDesc),
}

/// `Texture(format: .., size: .., history: ..)` (RON's unwrapped newtype).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureDesc {
    /// Texel format.
    pub format: TexFormat,
    /// Size; the render size when omitted.
    #[serde(default)]
    pub size: SizeDesc,
    /// Survives across frames (read at version 0 = last frame's result).
    #[serde(default)]
    pub history: bool,
    /// One texture that survives across frames, never pooled, written in
    /// place: what a pass that does not run every frame writes (a probe
    /// volume). Read before any write of a frame, it holds what the last
    /// write left, in whichever frame that was.
    #[serde(default)]
    pub persistent: bool,
}

/// A texture's or a dispatch's size, absolute or relative to the render size.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Default)]
pub enum SizeDesc {
    /// The render size.
    #[default]
    Screen,
    /// The render size times a factor (at least 1x1).
    Scaled(f32),
    /// A fixed size in texels (width, height).
    Fixed(u32, u32),
    /// One tile of w x h texels per probe of the graph's `probes` grid:
    /// (n^2 w) x (n h) for n probes per axis, probe (i, j, k) at tile
    /// (i + n j, k). Compile turns it into `Fixed`.
    ProbeTiles(u32, u32),
}

impl SizeDesc {
    /// Width and height in texels at render size `screen`; every side at least 1.
    pub fn resolve(self, screen: (u32, u32)) -> (u32, u32) {
        match self {
            SizeDesc::Screen => screen,
            SizeDesc::Scaled(s) => (
                ((screen.0 as f32 * s).round() as u32).max(1),
                ((screen.1 as f32 * s).round() as u32).max(1),
            ),
            SizeDesc::Fixed(w, h) => (w.max(1), h.max(1)),
            // Resolved by compile; a tile stands in for a graph without probes.
            SizeDesc::ProbeTiles(w, h) => (w.max(1), h.max(1)),
        }
    }

    /// `ProbeTiles` for `n` probes per axis as `Fixed`; others unchanged.
    pub fn for_probes(self, n: u32) -> SizeDesc {
        match self {
            SizeDesc::ProbeTiles(w, h) => SizeDesc::Fixed(n * n * w, n * h),
            other => other,
        }
    }
}

/// When a pass runs (`run:` in a graph). Passes that do not run every frame
/// may write only persistent resources, which keep what they wrote.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
pub enum RunMode {
    /// Every frame (the default).
    #[default]
    EveryFrame,
    /// In the first frame after the graph is built (load, reload).
    Once,
    /// In the first frame and in every frame whose scene changed (a light
    /// or object moved) since the pass last ran.
    OnSceneChange,
    /// In every frame whose scene changed since the pass last ran, when
    /// the frame has a history to compare with: not in the first frame
    /// after a start or a reset (a pass measuring what changed since last
    /// frame has nothing to measure then).
    OnSceneChangeWithHistory,
    /// In the first frame and in every frame where a pass that writes one
    /// of its inputs ran before it (a bake's second step after its first).
    OnInputChange,
    /// Every frame until the image has stood still (camera and scene as
    /// last frame) for `after` frames, then every `every`-th frame (and
    /// in a frame the engine shows in full, such as `glint render`'s
    /// last). For a denoiser's filter: its history goes on gathering
    /// samples every frame, while the image it shows changes less and
    /// less, so the frames between cost only the samples. The transients
    /// such a pass writes may be read only by passes of the same `run`.
    ThinWhenStill {
        /// Still frames filtered every frame.
        after: u32,
        /// Then one frame in this many.
        every: u32,
    },
    /// `per_frame` dispatches a frame, each one iteration (the `run`
    /// uniform counts them), until `until` iterations since the scene last
    /// changed (forever without `until`); a scene change starts the count
    /// again.
    Progressive {
        /// Dispatches (iterations) a frame.
        per_frame: u32,
        /// Iterations to run after a scene change; forever when omitted.
        #[serde(default)]
        until: Option<u32>,
    },
}

impl RunMode {
    /// Whether a pass of this mode fills persistent resources on a
    /// schedule of its own (a bake: not every frame, not only after its
    /// inputs, not a filter thinning still frames), which a session counts
    /// as work still to do (`Executor::updates_persistent`).
    pub fn bakes(self) -> bool {
        match self {
            RunMode::Once | RunMode::OnSceneChange | RunMode::OnSceneChangeWithHistory | RunMode::Progressive { .. } => true,
            RunMode::EveryFrame | RunMode::OnInputChange | RunMode::ThinWhenStill { .. } => false,
        }
    }

    /// Whether a `ThinWhenStill` pass runs in a frame `still` frames into
    /// a still image (None: a frame shown in full); None for other modes.
    pub fn thin_runs(self, still: Option<u32>) -> Option<bool> {
        match self {
            RunMode::ThinWhenStill { after, every } => Some(still.is_none_or(|s| s < after || s % every.max(1) == 0)),
            _ => None,
        }
    }

    /// As `graph check` prints it.
    pub fn describe(self) -> String {
        match self {
            RunMode::EveryFrame => "every frame".into(),
            RunMode::Once => "once, after the graph is built".into(),
            RunMode::OnSceneChange => "once, then whenever the scene changes".into(),
            RunMode::OnSceneChangeWithHistory => "whenever the scene changes, from the second frame of a history on".into(),
            RunMode::OnInputChange => "once, then whenever a pass writing its input ran".into(),
            RunMode::ThinWhenStill { after, every } => format!("every frame until the image has stood still {after} frames, then one frame in {every}"),
            RunMode::Progressive { per_frame, until: Some(u) } => {
                format!("{per_frame} iterations a frame until {u} since the scene last changed")
            }
            RunMode::Progressive { per_frame, until: None } => format!("{per_frame} iterations every frame"),
        }
    }
}

/// A value for one member of a pass's `params` uniform.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamValue {
    /// `true` or `false`, packed as 1 or 0.
    Bool(bool),
    /// An integer (fits `u32`, `i32` and `f32` members).
    Int(i64),
    /// A number with a fraction (`f32` members only).
    Float(f64),
    /// One number per component of a vector member.
    Vector(Vec<f64>),
}

/// Read by hand rather than as an untagged enum, whose error names serde's
/// internals (`data did not match any variant of untagged enum
/// ParamValue`): a value of the wrong kind says what a param value is.
impl<'de> Deserialize<'de> for ParamValue {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<ParamValue, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = ParamValue;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a param value: a number (`4`, `0.5`), `true` or `false`, or a list of numbers (`[1.0, 0.5, 0.2]`)")
            }
            fn visit_bool<E: serde::de::Error>(self, v: bool) -> Result<ParamValue, E> {
                Ok(ParamValue::Bool(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<ParamValue, E> {
                Ok(ParamValue::Int(v))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<ParamValue, E> {
                // Beyond i64 it is no u32 or i32 either: as a float, the
                // member's range check refuses it with its value.
                Ok(i64::try_from(v).map_or(ParamValue::Float(v as f64), ParamValue::Int))
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<ParamValue, E> {
                Ok(ParamValue::Float(v))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<ParamValue, A::Error> {
                let mut values = Vec::new();
                while let Some(v) = seq.next_element::<NumberOnly>()? {
                    values.push(v.0);
                }
                Ok(ParamValue::Vector(values))
            }
        }
        d.deserialize_any(Visitor)
    }
}

/// One component of a vector param: a number, nothing else.
struct NumberOnly(f64);

impl<'de> Deserialize<'de> for NumberOnly {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<NumberOnly, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = NumberOnly;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number (a vector param is a list of numbers, `[1.0, 0.5, 0.2]`)")
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<NumberOnly, E> {
                Ok(NumberOnly(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<NumberOnly, E> {
                Ok(NumberOnly(v as f64))
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<NumberOnly, E> {
                Ok(NumberOnly(v))
            }
        }
        d.deserialize_any(Visitor)
    }
}

/// One pass of a graph (`Pass(...)`): a compute shader and what it binds.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
#[serde(rename = "Pass")]
pub struct PassDesc {
    /// Unique within the graph; names it in messages, reports and timings.
    pub name: String,
    /// File name under `shaders/`.
    pub shader: String,
    /// Compute entry point; the shader's only one when omitted.
    #[serde(default)]
    pub entry: Option<String>,
    /// Members of the shader's `params` uniform, by name.
    #[serde(default, deserialize_with = "named_map")]
    pub params: BTreeMap<String, ParamValue>,
    /// WGSL `override` constants, by name.
    #[serde(default, deserialize_with = "named_map")]
    pub constants: BTreeMap<String, f64>,
    /// Scene features this pass needs; culled when the scene lacks one.
    #[serde(default)]
    pub requires: Vec<Feature>,
    /// Shader variable name -> graph resource name, for names that differ.
    #[serde(default, deserialize_with = "named_map")]
    pub bind: BTreeMap<String, String>,
    /// When the pass runs; every frame by default.
    #[serde(default)]
    pub run: RunMode,
    /// Invocations (x, y); by default one per texel of the first resource
    /// written.
    #[serde(default)]
    pub dispatch: Option<SizeDesc>,
    /// Texels each invocation renders in turn (1 to MAX_TEXELS_PER_INVOCATION;
    /// 1 when omitted): the dispatch is the size above with its width
    /// divided by this, rounded up, and the shader covers the rest
    /// (`shaders/pathtrace.wgsl`: a lane starts its next path when one
    /// ends). A pass with a sample loop takes at most as many as its
    /// scene's loop budget allows (8, or 32 where the scene is flat), and a
    /// split sample loop (`src/graph/compile/split.rs`) gives its first
    /// dispatch fewer samples per texel.
    #[serde(default)]
    pub texels_per_invocation: Option<u32>,
    /// A second entry point of the shader, run once per texel the pass's
    /// entry pushed to its `work_list` (shared/work_list.wgsl), by an
    /// indirect dispatch right after it: the expensive work of a pass that
    /// few texels need (reflections, refinement) then costs only those
    /// texels. CPU drivers run every branch of a shader under a lane mask,
    /// so a per-texel `if` skips nothing there; a shorter dispatch does.
    #[serde(default)]
    pub listed: Option<String>,
}

/// The most texels one invocation may render (`PassDesc::texels_per_invocation`).
pub const MAX_TEXELS_PER_INVOCATION: u32 = 64;

/// A map key written bare (`{ samples: 1 }`, as the shipped graphs write them) or quoted
/// (`{ "src": "lit" }`). Untagged enums go through serde's buffered content,
/// for which RON hands bare identifiers over as strings.
#[derive(Deserialize, PartialEq, Eq, PartialOrd, Ord)]
#[serde(untagged)]
enum Name {
    Name(String),
}

fn named_map<'de, D, V>(d: D) -> Result<BTreeMap<String, V>, D::Error>
where
    D: serde::Deserializer<'de>,
    V: Deserialize<'de>,
{
    let map: BTreeMap<Name, V> = BTreeMap::deserialize(d)?;
    Ok(map.into_iter().map(|(Name::Name(k), v)| (k, v)).collect())
}

impl FrameGraph {
    /// Parse graph text; `path` is for messages. Errors carry file, line and column.
    pub fn parse(text: &str, path: &Path) -> Result<FrameGraph, UserError> {
        // A UTF-8 byte order mark is not RON; editors may write one.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let graph: FrameGraph = ron::Options::default()
            .with_default_extension(
                ron::extensions::Extensions::UNWRAP_VARIANT_NEWTYPES | ron::extensions::Extensions::IMPLICIT_SOME,
            )
            .from_str(text)
            .map_err(|e| ron_error(path, &e))?;
        graph.check_sizes(text, path)?;
        Ok(graph)
    }

    /// Texture and dispatch sizes RON accepts but no texture or dispatch
    /// has (`check_size`), and bad probe grids.
    fn check_sizes(&self, text: &str, path: &Path) -> Result<(), UserError> {
        for (name, r) in &self.resources {
            let ResourceDesc::Texture(t) = r;
            let bad = self.check_size(t.size).or_else(|| {
                (t.history && t.persistent).then(|| "is both `history` (two textures, alternating) and `persistent` (one texture); pick one".to_string())
            });
            if let Some(message) = bad {
                let line = crate::error::line_of(text, &format!("\"{name}\"")).unwrap_or(0);
                return Err(UserError::at(crate::error::Location::at(path, line, 0), format!("resource `{name}`: {message}")));
            }
        }
        for pass in &self.passes {
            if let Some(message) = pass.dispatch.and_then(|d| self.check_size(d)) {
                let line = crate::graph::pass_line(text, &pass.name).unwrap_or(0);
                let message = format!("pass `{}`: dispatch {message}", pass.name);
                return Err(UserError::at(crate::error::Location::at(path, line, 0), message));
            }
        }
        if let Some(p) = &self.probes {
            let bad = if p.level == 0 || p.level > MAX_PROBE_LEVEL {
                Some(format!("`level: {}`: between 1 and {MAX_PROBE_LEVEL} ((L+1)^3 probes)", p.level))
            } else if !(p.padding.is_finite() && (0.0..0.5).contains(&p.padding)) {
                Some(format!("`padding: {}`: a fraction of the scene's extent in [0, 0.5)", p.padding))
            } else {
                None
            };
            if let Some(message) = bad {
                let line = crate::error::line_of(text, "probes:").unwrap_or(0);
                return Err(UserError::at(crate::error::Location::at(path, line, 0), format!("probes: {message}")));
            }
        }
        Ok(())
    }

    /// What is wrong with a texture's or a dispatch's size, if anything: a
    /// scale that is not a positive finite number (NaN, inf, 0, negative)
    /// or that makes a side of a 16384-pixel screen overflow, fixed sides
    /// of 0, tiles without a probe grid.
    fn check_size(&self, size: SizeDesc) -> Option<String> {
        match size {
            SizeDesc::Scaled(s) if !(s.is_finite() && s > 0.0 && s <= 16.0) => {
                Some(format!("`Scaled({s})`: the scale must be a finite number in (0, 16]"))
            }
            SizeDesc::Fixed(w, h) if w == 0 || h == 0 => Some(format!("`Fixed({w}, {h})` is empty: both sides must be at least 1")),
            SizeDesc::ProbeTiles(w, h) => self.check_tiles(w, h).err(),
            _ => None,
        }
    }

    /// A `ProbeTiles(w, h)` size: non-empty tiles, a `probes` grid to tile,
    /// and an atlas within a texture's side.
    pub fn check_tiles(&self, w: u32, h: u32) -> Result<(), String> {
        let Some(p) = &self.probes else {
            return Err(format!("`ProbeTiles({w}, {h})` needs the graph's `probes: (mode: .., level: ..)` grid"));
        };
        let n = u64::from(p.per_axis());
        let (aw, ah) = (n * n * u64::from(w), n * u64::from(h));
        if w == 0 || h == 0 {
            Err(format!("`ProbeTiles({w}, {h})` is empty: both sides must be at least 1"))
        } else if aw > 16384 || ah > 16384 {
            Err(format!("`ProbeTiles({w}, {h})` at probe level {} makes a {aw}x{ah} atlas, beyond 16384 texels a side; lower the level or the tile", p.level))
        } else {
            Ok(())
        }
    }

    /// Read and parse a graph file.
    pub fn load(path: &Path) -> Result<FrameGraph, UserError> {
        let text = crate::error::read_user_text(path, "graph file")?;
        Self::parse(&text, path)
    }
}
