//! The flags of what a method learns over a game loop's frames, made from the methods' own
//! descriptions (`MethodKind::learning_settings`: the path tracer's `--world-cache`,
//! `--light-reuse`), for the commands with frames to learn over (`view`, `bench game`); a
//! still's `render` has none. This file names no method.

use anyhow::Result;
use clap::{ArgMatches, Command};
use platoon::core::Method;

use crate::method_args::{as_flag, given_in, given_to, with_flags, Given};

/// Every learning setting given on the command line, of any method, with its flag.
#[derive(Debug, Default)]
pub struct LearningArgs {
    given: Given,
}

impl LearningArgs {
    /// `method` learning as the flags say; refuses one method's flags given to another.
    pub fn apply(&self, method: Method) -> Result<Method> {
        let kind = method.kind();
        let given = given_to(&self.given, kind)?;
        kind.with_learning(method, &given)
            .map_err(|e| as_flag(kind, e))
    }
}

impl clap::Args for LearningArgs {
    fn augment_args(cmd: Command) -> Command {
        with_flags(cmd, |k| k.learning_settings())
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}

impl clap::FromArgMatches for LearningArgs {
    fn from_arg_matches(m: &ArgMatches) -> Result<Self, clap::Error> {
        let given = given_in(m, |k| k.learning_settings());
        Ok(LearningArgs { given })
    }

    fn update_from_arg_matches(&mut self, m: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(m)?;
        Ok(())
    }
}
