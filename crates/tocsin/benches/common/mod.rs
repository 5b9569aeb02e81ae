//! Helpers shared by the bench programs.

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use tocsin::Vec3;

/// A uniformly random unit vector (rejection sampling in the unit ball).
pub fn unit(rng: &mut ChaCha8Rng) -> Vec3 {
    loop {
        let v = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        if v.length() > 0.2 && v.length() <= 1.0 {
            return v.normalize();
        }
    }
}
