//! The .msg parser and code generator of build.rs, exercised directly on good and bad message text.

#[allow(dead_code)]
#[path = "../crates/msgs/build.rs"]
mod build_script;

/// The package.xml roslibrust_codegen (build.rs's parser) reads a package's name and ROS version from.
fn package_xml(pkg_dir: &std::path::Path) {
    let name = pkg_dir.file_name().unwrap().to_str().unwrap();
    let xml =
        format!("<package format=\"3\"><name>{name}</name><buildtool_depend>ament_cmake</buildtool_depend></package>");
    std::fs::write(pkg_dir.join("package.xml"), xml).unwrap();
}

fn parse(text: &str) -> Result<String, Vec<String>> {
    let dir = tempfile::tempdir().unwrap();
    let msg_dir = dir.path().join("demo_msgs/msg");
    std::fs::create_dir_all(&msg_dir).unwrap();
    std::fs::write(msg_dir.join("Thing.msg"), text).unwrap();
    let vendored = dir.path().join("ros_interfaces/builtin_interfaces/msg");
    std::fs::create_dir_all(&vendored).unwrap();
    std::fs::write(vendored.join("Time.msg"), "int32 sec\nuint32 nanosec\n").unwrap();
    package_xml(msg_dir.parent().unwrap());
    package_xml(vendored.parent().unwrap());
    build_script::generate(dir.path())
}

#[test]
fn msgs_generator_accepts_the_full_grammar() {
    let text = "\
# A demo.

# constants
int32 ANSWER=42
string GREETING=\"hi # not a comment\" # a comment
float64 PI = 3.14159
bool FLAG=true
bool a
byte b
char c
int8 d -3
uint64 e 18446744073709551615
float32 f 1.5
string g \"default\"
string<=8 h
float64[] i
float64[3] j [1.0, 2.0, 3.0]
int32[<=4] k [1, 2]
builtin_interfaces/Time l
Thing2[] m
string[2] n [\"a\", \"b,c\"]
";
    let text2 = "uint8 x\n";
    let dir = tempfile::tempdir().unwrap();
    let msg_dir = dir.path().join("demo_msgs/msg");
    std::fs::create_dir_all(&msg_dir).unwrap();
    std::fs::write(msg_dir.join("Thing.msg"), text).unwrap();
    std::fs::write(msg_dir.join("Thing2.msg"), text2).unwrap();
    let v = dir.path().join("ros_interfaces/builtin_interfaces/msg");
    std::fs::create_dir_all(&v).unwrap();
    std::fs::write(v.join("Time.msg"), "int32 sec\nuint32 nanosec\n").unwrap();
    package_xml(msg_dir.parent().unwrap());
    package_xml(v.parent().unwrap());
    let code = build_script::generate(dir.path()).expect("valid grammar");
    for needle in [
        "pub const ANSWER: i32 = 42_i32;",
        "pub const GREETING: &'static str = \"hi # not a comment\";",
        "pub const PI: f64 = 3.14159_f64;",
        "pub const FLAG: bool = true;",
        "pub d: i8,",
        "d: -3_i8,",
        "e: 18446744073709551615_u64,",
        "g: \"default\".to_string(),",
        "pub j: [f64; 3],",
        "j: [1.0_f64, 2.0_f64, 3.0_f64],",
        "k: vec![1_i32, 2_i32],",
        "pub l: crate::builtin_interfaces::msg::Time,",
        "pub m: ::std::vec::Vec<crate::demo_msgs::msg::Thing2>,",
        "n: [\"a\".to_string(), \"b,c\".to_string()],",
        "const DDS_TYPE_NAME: &'static str = \"demo_msgs::msg::dds_::Thing_\";",
        "MSG: builtin_interfaces/Time",
        "MSG: demo_msgs/Thing2",
    ] {
        assert!(code.contains(needle), "generated code lacks `{needle}`:\n{code}");
    }
    // Deterministic: generating twice gives the same text.
    assert_eq!(code, build_script::generate(dir.path()).unwrap());
    // rosbag2 order: dependencies sorted by name (builtin_interfaces/Time before demo_msgs/Thing2).
    let t = code.find("MSG: builtin_interfaces/Time").unwrap();
    let t2 = code.find("MSG: demo_msgs/Thing2").unwrap();
    assert!(t < t2);
}

fn expect_error(text: &str, line: usize, words: &str) {
    let errors = parse(text).expect_err(text);
    let joined = errors.join("\n");
    assert!(joined.contains(&format!("Thing.msg:{line}: ")), "no file:line {line} in {joined}");
    assert!(joined.contains(words), "expected `{words}` in {joined}");
}

#[test]
fn msgs_generator_reports_errors_with_file_and_line() {
    expect_error("int32 a\nfloat65 b\n", 2, "float65");
    expect_error("# c\nint32 BadName\n", 2, "lower_snake_case");
    expect_error("int32 a\nint32 a\n", 2, "duplicate");
    expect_error("uint8 x 300\n", 1, "not a valid uint8");
    expect_error("uint8 lower=3\n", 1, "UPPER_CASE");
    expect_error("float64[0] a\n", 1, "size 0");
    expect_error("int32\n", 1, "expected `<type> <name>`");
    expect_error("other_msgs/Missing a\n", 1, "unknown type");
    expect_error("wstring w\n", 1, "wstring");
    expect_error("string<=2 s \"long\"\n", 1, "bound");
    expect_error("int32[2] a [1, 2, 3]\n", 1, "expected 2 elements");
}

#[test]
fn msgs_generator_refuses_a_package_without_package_xml() {
    let dir = tempfile::tempdir().unwrap();
    let msg_dir = dir.path().join("demo_msgs/msg");
    std::fs::create_dir_all(&msg_dir).unwrap();
    std::fs::write(msg_dir.join("Thing.msg"), "int32 a\n").unwrap();
    let errors = build_script::generate(dir.path()).expect_err("no package.xml").join("\n");
    assert!(errors.contains("demo_msgs: no package.xml"), "{errors}");
}

#[test]
fn msgs_generator_refuses_a_line_roslibrust_reads_otherwise() {
    // roslibrust_codegen takes any line with `=` after the type for a constant; sweetspot's scan reads a field
    // with a default. The two readings must agree, or the build fails at that line.
    expect_error("int32 a\nstring s \"x=y\"\n", 2, "does not read `s` as a field");
}

#[test]
fn msgs_generator_refuses_two_packages_of_one_name() {
    // roslibrust_codegen keeps one of them; the files of the other must not silently disappear.
    let dir = tempfile::tempdir().unwrap();
    for folder in ["a_msgs", "b_msgs"] {
        let pkg = dir.path().join(folder);
        std::fs::create_dir_all(pkg.join("msg")).unwrap();
        std::fs::write(
            pkg.join("msg").join(format!("{}.msg", folder.replace("_msgs", "").to_uppercase())),
            "int32 a\n",
        )
        .unwrap();
        let xml =
            "<package format=\"3\"><name>demo_msgs</name><buildtool_depend>ament_cmake</buildtool_depend></package>";
        std::fs::write(pkg.join("package.xml"), xml).unwrap();
    }
    let errors = build_script::generate(dir.path()).expect_err("one name, two packages").join("\n");
    assert!(errors.contains("package name taken twice"), "{errors}");
}
