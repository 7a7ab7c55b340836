//! A mouse-orbit camera: yaw and pitch around a target, at a distance.

use glam::{Mat4, Vec2, Vec3};

/// The camera's vertical field of view.
const FOV_Y: f32 = 0.9;

/// An orbit camera (right-handed, y up).
#[derive(Clone, Copy, Debug)]
pub struct OrbitCamera {
    /// The point looked at.
    pub target: Vec3,
    /// Turn around the vertical axis, radians.
    pub yaw: f32,
    /// Elevation above the horizon, radians.
    pub pitch: f32,
    /// Distance from the target.
    pub distance: f32,
}

impl Default for OrbitCamera {
    fn default() -> Self {
        OrbitCamera { target: Vec3::new(0.0, 2.0, 0.0), yaw: 0.6, pitch: 0.45, distance: 28.0 }
    }
}

impl OrbitCamera {
    /// The eye's position.
    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + self.distance * Vec3::new(cp * sy, sp, cp * cy)
    }

    /// World to clip space (wgpu's: z in 0..1) for a viewport of `aspect`.
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        let proj = glam::camera::rh::proj::directx::perspective(
            FOV_Y,
            aspect.max(1e-3),
            0.1,
            self.distance * 20.0 + 500.0,
        );
        proj * glam::camera::rh::view::look_at_mat4(self.eye(), self.target, Vec3::Y)
    }

    /// Pixels per unit of size at unit distance, in a viewport `height`
    /// pixels high: a sphere of radius r at distance d spans about
    /// `r * pixels_per_unit(height) / d` pixels in radius.
    pub fn pixels_per_unit(&self, height: f32) -> f32 {
        height / (2.0 * (FOV_Y / 2.0).tan())
    }

    /// Orbits by a mouse drag of `delta` points.
    pub fn orbit(&mut self, delta: Vec2) {
        self.yaw -= delta.x * 0.008;
        self.pitch = (self.pitch + delta.y * 0.008).clamp(-0.1, 1.5);
    }

    /// Zooms by a scroll of `amount` points (positive: closer).
    pub fn zoom(&mut self, amount: f32) {
        self.distance = (self.distance * (-amount * 0.002).exp()).clamp(2.0, 400.0);
    }

    /// The ray through a point of the viewport, given in 0..1 from its top
    /// left: origin and unit direction.
    pub fn ray(&self, aspect: f32, at: Vec2) -> (Vec3, Vec3) {
        let inverse = self.view_proj(aspect).inverse();
        let ndc = Vec2::new(at.x * 2.0 - 1.0, 1.0 - at.y * 2.0);
        let near = inverse.project_point3(ndc.extend(0.0));
        let far = inverse.project_point3(ndc.extend(1.0));
        (near, (far - near).normalize_or(Vec3::NEG_Z))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sphere's radius in pixels, measured on the projected image of a
    /// point on its rim seen square-on, is what `pixels_per_unit` says.
    #[test]
    fn pixels_per_unit_matches_the_projection() {
        let camera = OrbitCamera { yaw: -0.7, pitch: 0.8, distance: 17.0, ..Default::default() };
        let (width, height) = (1280.0, 720.0);
        let view_proj = camera.view_proj(width / height);
        let eye = camera.eye();
        let forward = (camera.target - eye).normalize();
        let up = forward.cross(Vec3::Y).cross(forward).normalize();
        for (distance, radius) in [(5.0, 0.5), (17.0, 1.0), (60.0, 0.3)] {
            let centre = eye + forward * distance;
            let to_pixels = |p: Vec3| view_proj.project_point3(p).y * height / 2.0;
            let measured = (to_pixels(centre + up * radius) - to_pixels(centre)).abs();
            let predicted = radius * camera.pixels_per_unit(height) / distance;
            assert!((measured / predicted - 1.0).abs() < 1e-3, "{measured} vs {predicted}");
        }
    }

    /// A ray through the viewport's centre points at the target, and a point
    /// projected back lands where the ray through its pixel goes.
    #[test]
    fn rays_invert_the_projection() {
        let camera = OrbitCamera { yaw: 1.1, pitch: 0.3, ..Default::default() };
        let aspect = 16.0 / 9.0;
        let (origin, dir) = camera.ray(aspect, Vec2::splat(0.5));
        let to_target = (camera.target - origin).normalize();
        assert!(dir.dot(to_target) > 1.0 - 1e-5);
        let p = Vec3::new(3.0, 1.0, -2.0);
        let clip = camera.view_proj(aspect).project_point3(p);
        let at = Vec2::new((clip.x + 1.0) / 2.0, (1.0 - clip.y) / 2.0);
        let (origin, dir) = camera.ray(aspect, at);
        let off = (p - origin) - dir * (p - origin).dot(dir);
        assert!(off.length() < 1e-3, "the ray misses the point by {}", off.length());
    }
}
