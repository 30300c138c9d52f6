//! AFL++ target: the Stl front end (`plcc check` of one `.stl` file).
fn main() {
    afl::fuzz!(|data: &[u8]| {
        plcc_fuzz::check(data, plcc_frontend::Lang::Stl, "fuzz.stl");
    });
}
