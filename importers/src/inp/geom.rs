//! Instance positioning and `*SYSTEM` local systems.

/// `x → m·x + t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Affine {
    m: [[f64; 3]; 3],
    t: [f64; 3],
}

impl Affine {
    pub(super) fn translation(t: [f64; 3]) -> Affine {
        Affine {
            m: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            t,
        }
    }

    pub(super) fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        let mut out = self.t;
        for (r, o) in out.iter_mut().enumerate() {
            *o += self.m[r][0] * p[0] + self.m[r][1] * p[1] + self.m[r][2] * p[2];
        }
        out
    }

    /// `self` after `first`: `x → self(first(x))`.
    pub(super) fn after(&self, first: &Affine) -> Affine {
        let mut m = [[0.0; 3]; 3];
        for (r, row) in m.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate() {
                *v = (0..3).map(|k| self.m[r][k] * first.m[k][c]).sum();
            }
        }
        Affine {
            m,
            t: self.apply(first.t),
        }
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

fn unit(a: [f64; 3]) -> Option<[f64; 3]> {
    let n = norm(a);
    (n > 0.0 && n.is_finite()).then(|| [a[0] / n, a[1] / n, a[2] / n])
}

/// Rotation by `angle_deg` (right-handed) about the axis through `a` and `b`.
pub(super) fn rotation_about(a: [f64; 3], b: [f64; 3], angle_deg: f64) -> Option<Affine> {
    let k = unit(sub(b, a))?;
    let (s, c) = angle_deg.to_radians().sin_cos();
    let v = 1.0 - c;
    let m = [
        [
            c + k[0] * k[0] * v,
            k[0] * k[1] * v - k[2] * s,
            k[0] * k[2] * v + k[1] * s,
        ],
        [
            k[1] * k[0] * v + k[2] * s,
            c + k[1] * k[1] * v,
            k[1] * k[2] * v - k[0] * s,
        ],
        [
            k[2] * k[0] * v - k[1] * s,
            k[2] * k[1] * v + k[0] * s,
            c + k[2] * k[2] * v,
        ],
    ];
    // x' = a + R (x - a)
    let r = Affine { m, t: [0.0; 3] };
    let ra = r.apply(a);
    Some(Affine { m, t: sub(a, ra) })
}

/// A local rectangular system from `*SYSTEM`: origin `a`, point `b` on the local x-axis,
/// point `c` in the local x-y plane. Without `c` the z-axis stays global Z and the x-axis is
/// `b - a` projected onto the X-Y plane.
pub(super) fn local_system(
    a: [f64; 3],
    b: Option<[f64; 3]>,
    c: Option<[f64; 3]>,
) -> Option<Affine> {
    let Some(b) = b else {
        return Some(Affine::translation(a));
    };
    let (x, z) = match c {
        Some(c) => {
            let x = unit(sub(b, a))?;
            let z = unit(cross(x, sub(c, a)))?;
            (x, z)
        }
        None => {
            let d = sub(b, a);
            (unit([d[0], d[1], 0.0])?, [0.0, 0.0, 1.0])
        }
    };
    let y = cross(z, x);
    Some(Affine {
        m: [[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]],
        t: a,
    })
}
