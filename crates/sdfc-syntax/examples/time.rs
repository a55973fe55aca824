use std::io::Read;
fn main() {
    let mut s = String::new();
    std::io::stdin().read_to_string(&mut s).unwrap();
    let t = std::time::Instant::now();
    let r = sdfc_syntax::parse(&s);
    println!("{:?} ok={} n={}", t.elapsed(), r.is_ok(), r.as_ref().map_or_else(|d| d.len(), |f| f.items.len()));
}
