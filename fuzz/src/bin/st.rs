//! AFL++ target: the St front end (`plcc check` of one `.st` file).
fn main() {
    afl::fuzz!(|data: &[u8]| {
        plcc_fuzz::check(data, plcc_frontend::Lang::St, "fuzz.st");
    });
}
