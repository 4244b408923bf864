use dcol::*;
fn main() {
    let (ra, rb) = (0.7, 1.3);
    let (a, b) = (Shape::sphere(ra).unwrap(), Shape::sphere(rb).unwrap());
    let dir = Vec3::new(0.3, -0.5, 0.8).normalize();
    for g in [1e-12, 1e-10, 1e-8, 1e-4] {
        let r1 = Vec3::new(0.3, -0.2, 0.1);
        let r2 = r1 + dir * (ra + rb + g * 1.3);
        let p1 = Pose::new(r1.into(), [0.9, 0.1, -0.3, 0.2]).unwrap();
        let p2 = Pose::new(r2.into(), [1.3, -0.4, 0.5, 0.7]).unwrap();
        let d = distance(&a, &p1, &b, &p2, &Options::default()).unwrap();
        println!("{g:e}: {d:?} dir {dir:?}");
    }
}
