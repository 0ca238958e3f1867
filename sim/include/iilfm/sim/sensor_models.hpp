// The LiDARs the simulator can imitate: how each one sweeps its beams, how fast, and how noisy.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace iilfm::sim {

enum class ScanPattern {
  kRosette,   // Livox-style Risley prisms: a non-repeating flower inside a circular or elliptical
              // cone
  kSpinning,  // Velodyne-style: a column of fixed-elevation rings fired at every azimuth step
  kBand,      // Livox Mid-360-style: a few beams spinning through 360 deg while they sweep up and
              // down an elevation band at a rate that never locks to the spin
};

struct SensorModel {
  std::string name;  // sensor_model_names(): "mid40", "vlp16", "os1-64", ...
  ScanPattern pattern = ScanPattern::kRosette;
  double points_per_second = 0;
  double frame_rate_hz = 10;
  double range_sigma_m = 0;    // default 1-sigma range noise along the beam
  double intensity_sigma = 4;  // default additive intensity noise (same units as the print)
  // Intensity falls with range and incidence (an Ouster's `intensity` field is a photon count)
  // rather than being calibrated reflectivity (Livox, Velodyne).
  bool raw_intensity = false;
  // The sensor's own scale for calibrated returns (SimOptions::IntensityModel::kSensor): (return,
  // reported) anchors, rising; linear between them and beyond the end ones, clamped to 0..255.
  // Empty: the returns as they are. Hesai's scale is offset and compressed (xt32()).
  std::vector<std::pair<double, double>> intensity_curve;
  double min_range_m = 0, max_range_m = 0;
  double fov_deg = 0;    // rosette: full cone angle (Mid-40: 38.4); horizontal if fov_v_deg is set
  double fov_v_deg = 0;  // rosette: full vertical angle of an elliptical cone; 0 = circular
  // Band: the elevations swept (lowest, highest) and the number of beams sweeping them.
  double band_low_deg = 0, band_high_deg = 0;
  int band_beams = 0;
  std::vector<double> ring_elevations_deg;  // spinning: index = ring number, ring 0 lowest
  double azimuth_step_deg = 0;              // spinning: column step
  // Spinning: how far each ring's beam points clockwise (the spin direction) of its column's
  // azimuth, degrees, index = ring number: the lasers of a column fire a few microseconds apart
  // (Velodyne) or look through the optics at fixed horizontal offsets (Hesai), and drivers give
  // each point its own azimuth, so the rings of one column fall up to a column apart. Empty: every
  // ring at the column's azimuth (Ouster's offsets are whole columns).
  std::vector<double> ring_azimuth_offsets_deg;
  // Full beam divergence across (horizontal, along the azimuth) and up (vertical): the footprint
  // a return's intensity is averaged over when SimOptions::footprint is on.
  double divergence_h_deg = 0, divergence_v_deg = 0;
};

SensorModel mid40();  // Livox Mid-40: 38.4 deg circular FoV, 100k pts/s, sigma 0.02 m
// Livox Avia, non-repetitive mode: 70.4 x 77.2 deg, 240k pts/s, sigma 0.02 m (an elliptical
// rosette standing in for the real six-beam pattern; docs/simulator.md).
SensorModel avia();
SensorModel vlp16();        // Velodyne VLP-16: 16 rings -15..+15 deg, 0.2 deg columns, sigma 0.03 m
SensorModel vlp16_hires();  // Velodyne VLP-16 Hi-Res (Puck Hi-Res): 16 rings -10..+10 deg, 1.33 deg
SensorModel ultra_puck();   // Velodyne ULTRA Puck / VLP-32C: 32 non-uniform rings, 0.2 deg columns
SensorModel os1_64();       // Ouster OS1-64: 64 uniform rings over 45 deg, 1024 columns
SensorModel os1_128();      // Ouster OS1-128: 128 uniform rings over 45 deg, 2048 columns
SensorModel hdl32e();       // Velodyne HDL-32E: 32 rings -30.67..+10.67 deg, 0.16 deg columns
SensorModel hdl64e();       // Velodyne HDL-64E: 64 equally spaced rings -24.9..+2 deg, 2118 columns
SensorModel os0_128();      // Ouster OS0-128: 128 uniform rings over 90 deg, 1024 columns
SensorModel os2_128();      // Ouster OS2-128: 128 uniform rings over 22.5 deg, 1024 columns
SensorModel xt32();         // Hesai PandarXT-32: 32 rings -16..+15 deg, 0.18 deg, Hesai's scale
SensorModel pandar40p();    // Hesai Pandar40P: 40 rings -25..+15 deg, 1/3 deg around the horizon
// The other Ouster units (32 or 64 uniform rings over their family's field, 1024 columns) and the
// RoboSense RS-LiDAR-16 (16 rings -15..+15 deg, 0.2 deg columns).
SensorModel os0_32();
SensorModel os0_64();
SensorModel os1_32();
SensorModel os2_32();
SensorModel os2_64();
SensorModel rs16();
// Hesai Pandar64: 64 rings -25..+15 deg, 1/6 deg from -6 to +2 deg, as the bundled real frames.
SensorModel pandar64();
// Hesai PandarQT64: 64 rings -52.1..+52.1 deg, 0.6 deg columns, channels 5-9 deg off the column.
SensorModel qt64();
// Livox Mid-70: the Mid-40's rosette over a 70.4 deg circular FoV.
SensorModel mid70();
// Velodyne VLP-32C: the ULTRA Puck's layout (the same sensor family).
SensorModel vlp32c();
// Livox Horizon (81.7 x 25.1 deg, 240k pts/s) and HAP (120 x 25 deg, 452k pts/s): elliptical
// rosettes standing in for their real patterns, as the Avia's (docs/simulator.md).
SensorModel horizon();
SensorModel hap();
// Livox Mid-360: 360 deg by -7..+52 deg, 200k pts/s, four beams on a band pattern standing in for
// the real one (docs/simulator.md).
SensorModel mid360();
// RoboSense RS-LiDAR-32: 32 rings -25..+15 deg, 1/3 deg around the horizon, channels 2-8 deg off
// their column (the maker's sample calibration).
SensorModel rs32();

// The model with this lower-case name; InputError listing the known names otherwise.
SensorModel sensor_model(const std::string& name);

// Names sensor_model() accepts, in a stable order.
std::vector<std::string> sensor_model_names();

// `intensity` on the sensor's own scale (SensorModel::intensity_curve).
double reported_intensity(const SensorModel& sensor, double intensity);

// Points in one frame (one 1/frame_rate_hz period).
int points_per_frame(const SensorModel& sensor);

// Frames a scan integrates unless told otherwise: a non-repetitive scanner needs seconds before a
// marker's cells fill in (40 frames); one sweep of a spinning sensor is what its driver publishes.
int default_frames(const SensorModel& sensor);

}  // namespace iilfm::sim
