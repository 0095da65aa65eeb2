//! What the `import` and `locate` tests share: their fixture files and the import options of the CLI's
//! defaults (the R161 with its preset BatParams, the default baseball, the typical batter, no undercut).

use std::path::PathBuf;

use sweetspot::import::ImportOptions;
use sweetspot::model::convert::{params_from_ball, params_of_preset};
use sweetspot::msgs::std_msgs::msg::Header;
use sweetspot::physics::batter::Batter;
use sweetspot::physics::{Ball, Bat};

/// A fixture file under tests/data (its README says where each comes from).
pub fn data(name: &str) -> PathBuf {
    super::repo().join("tests/data").join(name)
}

/// Import options as the CLI's defaults give them: any format, the R161, the default baseball, the typical
/// batter for the R161, undercut 0, no column map.
pub fn options() -> ImportOptions {
    let bat = Bat::preset("r161").unwrap();
    let batter = Batter::typical(bat.mass_properties()).unwrap();
    ImportOptions {
        format: None,
        bat,
        bat_params: params_of_preset("r161", "r161", Header::default()),
        ball_params: params_from_ball("baseball", &Ball::default(), None, Header::default()),
        batter,
        undercut: 0.0,
        map: None,
        tee: false,
    }
}
