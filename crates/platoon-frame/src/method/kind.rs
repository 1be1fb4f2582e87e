//! A rendering method as a user chooses it: its name, its settings described once, how they
//! make the frame's `Method`, and what it asks of the layers above (whether it travels between
//! ranks, the sweep it is compared in). One entry of `registry::KINDS` per method.

use super::settings::{Setting, Settings};
use super::Method;

/// Named groups of settings a technique may give at once (IGI's `all`): the name, then each
/// setting's key and value as written.
pub type Preset = (&'static str, &'static [(&'static str, &'static str)]);

pub trait MethodKind: Sync {
    /// Its name: `--method NAME`, techniques' `NAME=...`, the wire.
    fn name(&self) -> &'static str;
    /// Its name in messages (`IGI`, `vertex links`).
    fn title(&self) -> &'static str;
    /// One line for `--method`'s help.
    fn summary(&self) -> &'static str;
    /// Its options, in the order help and technique strings list them.
    fn settings(&self) -> &'static [Setting];
    /// The method with the `given` settings and the rest default, validated: an error names
    /// the setting (as `key: problem` where it is one setting's, which front ends write as
    /// their flag or keyword: `split_setting`).
    fn build(&self, given: &Settings) -> Result<Method, String>;
    /// Every setting of `method` (one of this kind), so that `build` of them renders what
    /// `method` renders (the wire sends these).
    fn settings_of(&self, method: &Method) -> Settings;
    /// The setting a technique string gives right after `=` (`igi=180`: the VPLs).
    fn primary(&self) -> Option<&'static str> {
        None
    }
    fn presets(&self) -> &'static [Preset] {
        &[]
    }
    /// The techniques `platoon tradeoff --method NAME` compares by default.
    fn sweep(&self) -> &'static [&'static str];
    /// Whether its frames can be sent to another rank, and if not why.
    fn travels(&self) -> Result<(), String> {
        Ok(())
    }
    /// Its state in `method` beyond its settings, as bytes, for the wire and a frame's
    /// fingerprint (the path tracer's: the last paths cut, what its frames carry from one to the
    /// next); None where its settings say it all.
    fn state_bytes(&self, _method: &Method) -> Result<Option<Vec<u8>>, String> {
        Ok(None)
    }
    /// The method `state_bytes` gave `bytes` of, rebuilt on another rank (`settings` built
    /// the method it starts from).
    fn with_state(&self, _method: Method, _bytes: &[u8]) -> Result<Method, String> {
        Err(format!("{} has no state beyond its settings", self.name()))
    }
    /// Its settings of what it learns over a game loop's frames (the path tracer's world cache
    /// and light reuse): offered where there are frames to learn over (`platoon view`, the
    /// game bench), not by a still's render.
    fn learning_settings(&self) -> &'static [Setting] {
        &[]
    }
    /// `method` (of this kind) learning over frames as `given` says (keys of
    /// `learning_settings`); an error names the setting as `build`'s do.
    fn with_learning(&self, method: Method, given: &Settings) -> Result<Method, String> {
        match given.0.first() {
            None => Ok(method),
            Some((key, _)) => Err(format!(
                "{key}: {} learns nothing over frames",
                self.title()
            )),
        }
    }
    /// The learning settings `method` (of this kind) has on.
    fn learning_of(&self, _method: &Method) -> Settings {
        Settings::default()
    }
}

impl std::fmt::Debug for dyn MethodKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.name())
    }
}

impl PartialEq for dyn MethodKind {
    fn eq(&self, other: &Self) -> bool {
        self.name() == other.name()
    }
}

impl dyn MethodKind + '_ {
    /// `error` of `build` or `with_learning` as the setting it is about and the problem, where it begins with a
    /// setting's key (`kernel: unknown kernel warp...`).
    pub fn split_setting<'e>(&self, error: &'e str) -> Option<(&'static Setting, &'e str)> {
        let (key, problem) = error.split_once(": ")?;
        let learning = || self.learning_settings().iter().find(|s| s.key == key);
        self.setting(key).or_else(learning).map(|s| (s, problem))
    }

    /// The setting named `key`.
    pub fn setting(&self, key: &str) -> Option<&'static Setting> {
        self.settings().iter().find(|s| s.key == key)
    }

    /// Every setting's value when none is given.
    pub fn defaults(&self) -> Settings {
        let method = self
            .build(&Settings::default())
            .expect("a method's defaults are valid");
        self.settings_of(&method)
    }
}
