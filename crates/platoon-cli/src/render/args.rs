//! `platoon render`'s arguments: the still's and the animation's (`FrameArgs`).

use std::path::PathBuf;

use anyhow::Result;
use clap::ValueEnum;
use platoon::animation::FrameRange;
use platoon::core::frame::aov::Aov;

use crate::method_args::MethodArgs;
use crate::request_args::RequestArgs;
use crate::scene_args::SceneArgs;

#[derive(Clone, Copy, ValueEnum)]
pub enum MemoryArg {
    Auto,
    TexelBuffers,
    StorageBuffers,
    DeviceAddress,
}

#[derive(clap::Args)]
pub struct RenderArgs {
    #[command(flatten)]
    pub(super) scene: SceneArgs,
    #[command(flatten)]
    pub(super) method: MethodArgs,
    #[command(flatten)]
    pub(super) options: RequestArgs,
    /// Continue a still from its checkpoint (OUT.checkpoint, which a render ended short by
    /// Ctrl-C or --time-limit on one device leaves): the same command with --resume renders
    /// the samples left, the image the same bits as one uninterrupted render.
    #[arg(long, conflicts_with = "sequence")]
    pub(super) resume: bool,
    /// Render at this percentage of --width and --height (Blender's resolution %): 25 for a
    /// quick preview of the same framing.
    #[arg(long, default_value_t = 100, allow_negative_numbers = true)]
    pub(super) resolution_percent: u32,
    /// The scene camera by index (from 0) or name; the scene is framed from its bounds when it
    /// has none.
    #[arg(long)]
    pub(super) camera: Option<String>,
    /// A camera given instead of the scene's: where it stands, X,Y,Z in world space (with
    /// --look-at; --fov, --aperture and --focus-distance apply to it).
    #[arg(long, value_parser = crate::scene_args::parse_xyz, allow_hyphen_values = true,
          requires = "look_at", conflicts_with = "camera")]
    pub(super) camera_position: Option<glam::Vec3>,
    /// The point the given camera looks at, X,Y,Z (+Y is up).
    #[arg(long, value_parser = crate::scene_args::parse_xyz, allow_hyphen_values = true,
          requires = "camera_position")]
    pub(super) look_at: Option<glam::Vec3>,
    /// The given camera's vertical field of view in degrees.
    #[arg(
        long,
        default_value_t = 40.0,
        allow_negative_numbers = true,
        requires = "camera_position"
    )]
    pub(super) fov: f32,
    /// How the kernel reads scene arrays: auto is texel buffers on CPU devices (lavapipe before
    /// Mesa 25) and storage buffers on GPUs and newer lavapipe, each where the array fits the
    /// device's limits, else device addresses; the others force one path where it fits. Same
    /// image on every path.
    #[arg(long, value_enum, default_value = "auto")]
    pub(super) memory: MemoryArg,
    /// Device memory the scene may take on each device (bytes, or 512M, 2G...): a scene over
    /// it, or over what a device has, is refused before upload, naming the device and sizes.
    #[arg(long, value_parser = crate::bytes_arg::parse_bytes)]
    pub(super) device_memory_limit: Option<u64>,
    #[arg(long, short, default_value = "render.png")]
    pub(super) out: PathBuf,
    /// AOVs written as layers of the EXR beside the beauty, comma-separated: albedo, normal
    /// (Cycles' denoising conventions), depth, position, instance-id, material-id,
    /// primitive-id, variance (of each pixel's mean, from batches of its samples),
    /// sample-count, crypto-object, crypto-material, crypto-asset (Cryptomatte's layers and
    /// manifest), the light passes diffuse-direct, diffuse-indirect, glossy-direct,
    /// glossy-indirect, transmission-direct, transmission-indirect, emission, environment
    /// (summing to the beauty), or light for all eight; motion (pixels moved since the frame
    /// before: 1/fps earlier in a sequence, 1/24 s for a still); ao (ambient occlusion,
    /// --ao-distance); diffuse-color, glossy-color, transmission-color (the BSDF parts'
    /// colours).
    #[arg(long, value_parser = parse_aovs)]
    pub(super) aov: Option<AovList>,
    /// Samples every pixel takes before adaptive sampling may stop it (default: spp / 16, at
    /// least 16).
    #[arg(long, requires = "adaptive_threshold")]
    pub(super) adaptive_min_spp: Option<u32>,
    /// Split each frame between the ranks of an MPI job: `mpirun -n N platoon render ...
    /// --mpi`, in a build with `--features mpi`. Every rank loads the scene and renders on its
    /// own --devices; rank 0 cuts frames between the ranks with --balancer and writes the
    /// image (docs/DISTRIBUTED.md).
    #[arg(long)]
    pub(super) mpi: bool,
    #[command(flatten)]
    pub(super) frames: FrameArgs,
    #[command(flatten)]
    pub(super) display: crate::display_args::DisplayArgs,
}

#[derive(Clone, Debug)]
pub struct AovList(pub Vec<Aov>);

fn parse_aovs(s: &str) -> Result<AovList, String> {
    Aov::parse_list(s).map(AovList)
}

#[derive(clap::Args)]
pub struct FrameArgs {
    /// Say each frame on standard output as one JSON object a line (frame, status ok,
    /// skipped or failed, file, seconds, rank, error), for farm tools; a still says itself so
    /// at its end (status, file, seconds, spp, width, height, samples_per_second).
    #[arg(long)]
    pub log_json: bool,
    /// Render an animation: frames A..B[:STEP] (B included), frame F at animation time
    /// F / --fps seconds, to numbered files (`--out dir/shot_####.exr`: the last run of #
    /// takes the frame number; a name without # gets `_####`).
    #[arg(long, group = "sequence")]
    pub frames: Option<FrameRange>,
    /// Frames per second of the animation.
    #[arg(long, default_value_t = 24.0, requires = "sequence")]
    pub fps: f64,
    /// Render farms: the environment variable holding this task's index, counted from 0
    /// (Slurm: SLURM_ARRAY_TASK_ID with --array=0-N; a Kubernetes indexed job:
    /// JOB_COMPLETION_INDEX). The task renders chunk INDEX of the range cut into --chunk frames.
    #[arg(long, value_name = "VARIABLE", requires = "frames")]
    pub task_index: Option<String>,
    /// Frames per farm task (with --task-index).
    #[arg(long, default_value_t = 1, requires = "task_index")]
    pub chunk: usize,
    /// Render again frames whose file is already there with these settings (default: skip).
    #[arg(long, requires = "sequence")]
    pub overwrite: bool,
    /// A different noise pattern every frame (seed plus frame number), as Cycles' animated
    /// seed; by default every frame uses --seed, as a still render at its time would.
    #[arg(long, requires = "sequence")]
    pub animated_seed: bool,
    /// Prepare each frame from scratch (BVHs rebuilt, tracers created anew) instead of
    /// carrying the scene from frame to frame with refits: what a loop of still renders costs.
    #[arg(long, requires = "sequence")]
    pub fresh_prepare: bool,
    /// A render farm over an MPI job (`mpirun -n N platoon render SCENE --mpi-frames 0..99
    /// --out shots/f_####.exr`, a build with `--features mpi`): rank 0 deals the frames
    /// A..B[:STEP] to the ranks as they finish, each rank renders whole frames on its own
    /// --devices and writes them, atomically, into the output folder, which the ranks must
    /// share; a rerun skips the frames done.
    #[arg(long, group = "sequence", conflicts_with_all = ["frames", "task_index", "mpi"])]
    pub mpi_frames: Option<FrameRange>,
    /// Also encode the frames as a video (e.g. shot.mp4) with ffmpeg, when it is installed
    /// (H.264 at --fps; EXR frames tone-mapped as PNGs are). Not with --task-index.
    #[arg(long, value_name = "FILE", requires = "frames")]
    pub video: Option<std::path::PathBuf>,
}
