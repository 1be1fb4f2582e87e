//! A balancer's name (`render --balancer`, `bench game --balancer`): one of the policies, each
//! with `+steal`.

use platoon::core::balance;

pub fn parse_balancer(s: &str) -> Result<String, String> {
    match balance::by_name(s) {
        Some(_) => Ok(s.to_string()),
        None => Err(format!("unknown balancer {s}: {}", balance::names_help())),
    }
}
