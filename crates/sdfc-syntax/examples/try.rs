use std::io::Read;
fn main() {
    let mut s = String::new();
    std::io::stdin().read_to_string(&mut s).unwrap();
    match sdfc_syntax::parse(&s) {
        Ok(f) => print!("{}", sdfc_syntax::pretty::dump(&f)),
        Err(d) => print!("{}", sdfc_syntax::diag::render("t.sdf", &s, &d)),
    }
}
