//! AFL++ target: the Ld front end (`plcc check` of one `.xml` file).
fn main() {
    afl::fuzz!(|data: &[u8]| {
        plcc_fuzz::check(data, plcc_frontend::Lang::Ld, "fuzz.xml");
    });
}
