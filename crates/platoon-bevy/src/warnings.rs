//! What the mirror could not carry into platoon, said once each.

use std::collections::HashSet;

#[derive(Default)]
pub struct Warnings {
    said: HashSet<String>,
    /// What was said and not yet handed to `PlatoonStats`.
    fresh: Vec<String>,
}

impl Warnings {
    /// Logs `message` the first time it comes.
    pub fn once(&mut self, message: String) {
        if self.said.insert(message.clone()) {
            log::warn!("platoon: {message}");
            self.fresh.push(message);
        }
    }

    /// The warnings said since the last call.
    pub fn take_fresh(&mut self) -> Vec<String> {
        std::mem::take(&mut self.fresh)
    }
}
