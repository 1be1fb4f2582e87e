//! A word of a frame's options that the kernel reads, declared beside its option: the frame's
//! options (`options::OPTION_WORDS`) and its path loop's knobs (`path_loop::LOOP_WORDS`). The
//! tracer lays them into the push constants in that order (`FrameParams::kernel_words`) and
//! writes their GLSL accessors from the same tables (`platoon-tracer/src/globals.rs`,
//! `frame_words_glsl`), so an option the kernel reads joins no mirror of the push block.

/// One word of `T` the kernel reads: the name of its GLSL accessor (a function), whether
/// the word holds an f32's bits, and its value.
pub struct KernelWord<T> {
    pub name: &'static str,
    pub float: bool,
    pub of: fn(&T) -> u32,
}
