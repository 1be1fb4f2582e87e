//! What every rendering method provides to the core, and how a frame's `Method` is read as the
//! unit that renders it.

use std::any::Any;
use std::sync::Arc;

use crate::flatten::features::{KernelOption, SceneFeatures};
use crate::flatten::GpuScene;
use crate::frame::{Band, FrameParams, MethodReport};
use crate::method::kind::MethodKind;
use crate::method::settings::Settings;
use crate::method::{Method, MethodState};

/// What a device frame of a method's work before its frames gave back: each pixel's average
/// (the film) and what its bands left per pixel (`Band::per_pixel`), in pixel order.
pub struct DeviceFrame {
    pub film: Vec<[f32; 3]>,
    pub per_pixel: crate::frame::PixelData,
    /// Device time of its dispatches, summed over tracers.
    pub gpu_time: std::time::Duration,
}

/// What a method tells the user after a render.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Report {
    pub lines: Vec<String>,
    pub warnings: Vec<String>,
}

/// Renders a device frame: on one tracer's bands, or split between the renderer's tracers.
pub type DeviceRun<'a> = dyn FnMut(&FrameParams) -> Result<DeviceFrame, String> + 'a;

/// A rendering method as the core sees it: plain data and CPU passes; its device side is the
/// tracer's (`platoon-tracer/src/method/`).
pub trait RenderMethod {
    /// How it is chosen: its name, settings and what it asks of the layers above.
    fn kind(&self) -> &'static dyn MethodKind;
    /// Its name on the command line and in the tracer's registry.
    fn name(&self) -> &'static str {
        self.kind().name()
    }
    /// The method and its options, for the output's metadata.
    fn describe(&self) -> String;
    /// What is wrong with rendering `params` this way, if anything.
    fn validate(&self, params: &FrameParams) -> Result<(), String>;
    /// The kernel defines of its options in a frame of `params` (what it outputs may switch
    /// some off), each with whether it is on: appended to the scene's features and the frame's
    /// options in the kernel variant (`variant::KernelVariant`).
    fn kernel_options(&self, params: &FrameParams) -> Vec<KernelOption>;
    /// Its biased parts, for the output's list of approximations.
    fn approximations(&self) -> Vec<String>;
    /// The pass after every band of the frame is in, on the bands' sums (what needs
    /// neighbouring pixels, from the data each band carries in `Band::per_pixel`).
    fn finish(&self, _params: &FrameParams, _bands: &mut [Band]) {}
    /// Its work before the frames that need it (vertex links' update), on `g` (the scene the
    /// tracers hold) through device frames: the method with the results, or None when the
    /// frame needs nothing more.
    fn prepare(
        &self,
        _g: &GpuScene,
        _params: &FrameParams,
        _run: &mut DeviceRun,
    ) -> crate::error::Result<Option<Method>> {
        Ok(None)
    }
    /// Whether its frames can render as they are (false: `prepare` must run first).
    fn ready(&self) -> bool {
        true
    }
    /// The method a preparation of a changed scene starts from, given this prepared one: its
    /// options with what this preparation made as the earlier result (what vertex links
    /// revalidate or relight from). None for a method with no preparation.
    fn renewal(&self) -> Option<Method> {
        None
    }
    /// A few words for a live view's status line (IGI's VPL count), if it has any to say.
    fn brief(&self) -> Option<String> {
        None
    }
    /// What a user should read after a render, from the frame's report (`Band::method_report`
    /// of its first band): lines to print, and warnings (layered hit buffers' build and lost
    /// layers).
    fn report(&self, _report: &MethodReport) -> Report {
        Report::default()
    }
    /// The frame's report as entries of the output's metadata.
    fn report_metadata(&self, _report: &MethodReport) -> Vec<(String, String)> {
        Vec::new()
    }
    /// Entries of the output's metadata beyond its description (what its preparation did).
    fn metadata(&self) -> Vec<(String, String)> {
        Vec::new()
    }
    /// Whether it reads the scene on the host beside its devices (vertex links' and layered hit
    /// buffers' preparations do): a still of a method that does not lets the host's copy of
    /// the large arrays go once its devices hold them.
    fn reads_scene_on_host(&self) -> bool {
        true
    }
    /// Whether its kernels skip the pixels adaptive sampling found converged (the path
    /// tracer's do): a method whose kernels render every pixel's samples is refused adaptive
    /// sampling.
    fn skips_converged_pixels(&self) -> bool {
        false
    }
    /// Whether its image is the sum of the light passes (`Aov::Light`: the beauty's paths
    /// rendered again by the path tracer's kernel, each pass keeping one kind of light): true
    /// where its beauty is those paths, as the path tracer's is.
    fn splits_into_light_passes(&self) -> bool {
        false
    }
    /// What it refuses of the scene a tracer holds (`features`: the path tracer's resampled
    /// light weighed by emitted luminance refuses punctual lights), checked at each band since
    /// only the tracer knows the scene it holds.
    fn check_scene(&self, _features: &SceneFeatures) -> Result<(), String> {
        Ok(())
    }
    /// The rules of its options that need no frame (what a request refuses before it loads
    /// anything): the setting it is about and the problem.
    fn check_options(&self) -> Result<(), (&'static str, String)> {
        Ok(())
    }
    /// How its paths pick lights where they pick them its own way (the path tracer's resampled
    /// light), as the metadata's `light_selection` says it; None: as the path loop picks them.
    fn light_selection(&self) -> Option<String> {
        None
    }
    /// It with a game's real-time settings where its options leave them open (the path
    /// tracer's resampled light); None where it has none.
    fn realtime(&self) -> Option<Method> {
        None
    }
    /// What it learns over a game loop's frames as its state asks (the path tracer's world
    /// cache and light reuse), in a scene whose bounding sphere has radius `scene_radius`: the
    /// learner a frame driver holds; None when its frames stand alone, an error when its
    /// state's learning settings cannot hold.
    fn learning(
        &self,
        _scene_radius: f32,
    ) -> Result<Option<Box<dyn crate::method::learning::FrameLearning>>, String> {
        Ok(None)
    }
}

/// Reads a `Method`'s state, of the type `Method::new` was given, as the unit it is.
struct ReadUnit(for<'a> fn(&'a dyn MethodState) -> &'a dyn RenderMethod);

fn read_unit<T: RenderMethod + MethodState>(state: &dyn MethodState) -> &dyn RenderMethod {
    let state: &T = state
        .as_any()
        .downcast_ref()
        .expect("the state Method::new was given");
    state
}

impl Method {
    /// The method whose state is `state` (a unit's options: `IgiOptions`, `Links`...), which
    /// renders it.
    pub fn new<T: RenderMethod + MethodState>(state: T) -> Method {
        Method::of_parts(Arc::new(state), const { &ReadUnit(read_unit::<T>) })
    }

    /// The method's unit: what renders it.
    pub fn unit(&self) -> &dyn RenderMethod {
        let (state, read) = self.parts();
        let read: &ReadUnit = (read as &dyn Any)
            .downcast_ref()
            .expect("made by Method::new");
        (read.0)(state)
    }

    /// How it is chosen: its settings and what it asks of the layers above.
    pub fn kind(&self) -> &'static dyn MethodKind {
        self.unit().kind()
    }

    /// Its settings, all of them.
    pub fn settings(&self) -> Settings {
        self.kind().settings_of(self)
    }
}
