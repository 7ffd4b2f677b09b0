//! Size effect: the accelerometers sit at lever arms from the navigation centre, so in rotation
//! they sense tangential and centripetal accelerations the navigation centre does not.

use super::{EffectContext, ExtraEffect};
use sins_nav::Vec3;

/// Size effect: accelerometer j sits at `r_j` (body axes) from the navigation centre where the
/// gyro rate and the navigation solution refer, so it senses
/// `δf_j = e_j · (ω̇ × r_j + ω × (ω × r_j))`, the tangential and centripetal accelerations of its
/// own position.
///
/// Computed from the true increments: `ω = dθ_k/dt` (mean rate of the sample) and
/// `ω̇ = (dθ_k - dθ_{k-1})/dt^2` (exact for a constant angular acceleration; it refers to the
/// start of the sample, half a sample before the mean rate), `δdv_j = δf_j dt`. Linear in the nine
/// lever-arm components. The centripetal part rectifies under angular vibration (a mean
/// `-<ω_⊥^2> r`), the tangential part is zero-mean but large (ω̇ r of order g for Table 4's
/// patterns at 10 mm). Proof masses of a navigation-grade cluster sit 10-40 mm from the
/// navigation centre and systems correct the nominal geometry; the unmodelled residual is ~1 mm,
/// which still rectifies to about 1e4 ug on Table 4's pattern 3 (measured over the 15 h run).
#[derive(Clone, Copy, Debug)]
pub struct SizeEffect {
    /// Lever arm (m, body axes) of the x, y and z accelerometer.
    pub lever_arm_m: [Vec3; 3],
}

impl ExtraEffect for SizeEffect {
    fn name(&self) -> &'static str {
        "size_effect"
    }
    fn apply(&mut self, ctx: &EffectContext, _dtheta: &mut Vec3, dv: &mut Vec3) {
        let w = ctx.mean_rate_radps();
        let w_dot = ctx.angular_accel_radps2();
        for (j, r) in self.lever_arm_m.iter().enumerate() {
            let a = w_dot.cross(r) + w.cross(&w.cross(r));
            dv[j] += a[j] * ctx.dt_s;
        }
    }

    /// [`Self::apply`] to zero increments, skipping the accelerometers at the centre: their
    /// term is a zero (finite rates), which leaves the zero they start from as it is.
    fn perturbations(&mut self, ctxs: &[EffectContext], out: &mut Vec<(Vec3, Vec3)>) {
        out.clear();
        let arms: Vec<(usize, Vec3)> = (self.lever_arm_m.iter().enumerate())
            .filter(|(_, r)| **r != Vec3::zeros())
            .map(|(j, r)| (j, *r))
            .collect();
        out.extend(ctxs.iter().map(|ctx| {
            let w = ctx.mean_rate_radps();
            let w_dot = ctx.angular_accel_radps2();
            let mut dv = Vec3::zeros();
            for &(j, r) in &arms {
                let a = w_dot.cross(&r) + w.cross(&w.cross(&r));
                dv[j] += a[j] * ctx.dt_s;
            }
            (Vec3::zeros(), dv)
        }));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rotating(prev_rate: Vec3, rate: Vec3, h: f64) -> EffectContext {
        let mut c = EffectContext::at_rest(1.0, h, [20.0; 3]);
        c.true_dtheta_rad = rate * h;
        c.prev_true_dtheta_rad = prev_rate * h;
        c
    }

    #[test]
    fn constant_rotation_gives_the_centripetal_acceleration() {
        let h = 0.005;
        // x accelerometer 10 mm out along x, y accelerometer 20 mm along x, z at the centre.
        let mut e = SizeEffect {
            lever_arm_m: [
                Vec3::new(0.01, 0.0, 0.0),
                Vec3::new(0.02, 0.0, 0.0),
                Vec3::zeros(),
            ],
        };
        // 90 deg/s about z: the x accelerometer senses -w^2 r (towards the axis).
        let w = 90f64.to_radians();
        let c = rotating(Vec3::new(0.0, 0.0, w), Vec3::new(0.0, 0.0, w), h);
        let (dth, dv) = e.perturbation(&c);
        assert_eq!(dth, Vec3::zeros());
        assert!((dv.x / h + w * w * 0.01).abs() < 1e-15);
        // The y accelerometer's lever arm is along x: its centripetal acceleration is along x,
        // orthogonal to its input axis.
        assert!(dv.y.abs() < 1e-18 && dv.z.abs() < 1e-18);
        // The sense of rotation does not matter (w^2).
        let c = rotating(Vec3::new(0.0, 0.0, -w), Vec3::new(0.0, 0.0, -w), h);
        assert!((e.perturbation(&c).1.x / h + w * w * 0.01).abs() < 1e-15);
        // Rotation about the lever arm itself: nothing.
        let c = rotating(Vec3::new(w, 0.0, 0.0), Vec3::new(w, 0.0, 0.0), h);
        assert!(e.perturbation(&c).1.norm() < 1e-18);
    }

    #[test]
    fn angular_acceleration_gives_the_tangential_acceleration() {
        let h = 0.005;
        // y accelerometer 10 mm out along x: w_dot about z gives w_dot r along +y.
        let mut e = SizeEffect {
            lever_arm_m: [Vec3::zeros(), Vec3::new(0.01, 0.0, 0.0), Vec3::zeros()],
        };
        let w_dot = 100.0;
        // Constant angular acceleration from rest: rates at the sample midpoints.
        let w0 = w_dot * 0.5 * h;
        let c = rotating(
            Vec3::new(0.0, 0.0, w0),
            Vec3::new(0.0, 0.0, w0 + w_dot * h),
            h,
        );
        let (_, dv) = e.perturbation(&c);
        assert!((dv.y / h - w_dot * 0.01).abs() < 1e-12, "{}", dv.y / h);
    }
}
