//! Small 3-vector arithmetic shared by the wrinkle figure and the pictures of the formed
//! blank (mm, N: plain `[f64; 3]`).

pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `a` over its length (unchanged when zero).
pub fn unit(a: [f64; 3]) -> [f64; 3] {
    let l = dot(a, a).sqrt();
    if l > 0.0 { a.map(|v| v / l) } else { a }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cross_product_is_normal_to_both_and_the_unit_vector_has_length_one() {
        let (a, b) = ([1.0, 2.0, 3.0], [-2.0, 0.5, 4.0]);
        let c = cross(a, b);
        assert!(dot(c, a).abs() < 1e-12 && dot(c, b).abs() < 1e-12);
        assert!((dot(unit(c), unit(c)) - 1.0).abs() < 1e-12);
        assert_eq!(sub(a, a), [0.0; 3]);
        assert_eq!(unit([0.0; 3]), [0.0; 3]);
    }
}
