// Reading a marker's cells from ring rows, and the ring-sample decoding stage, on a synthetic
// spinning-LiDAR image of a tag on a wall.
#include <gtest/gtest.h>

#include <algorithm>
#include <bitset>
#include <cmath>
#include <tuple>

#include "../../src/ring_cell_reader.hpp"
#include "../../src/ring_decoding.hpp"
#include "iilfm/apriltag_families.hpp"

namespace iilfm::detail {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A tag36h11 of black-square edge `size` facing a LiDAR `distance` ahead (plane x = distance),
// its centre `z0` above the sensor, seen by `rings` rings `ring_deg` apart and `column_deg`
// columns.
struct RingScene {
  ProjectedImage image;
  std::array<Vec2, 4> corners;  // black square, TL TR BR BL
  int id = 0;

  RingScene(int tag_id, double size, double distance, int rings, double ring_deg, double z0,
            double white = 100, double black = 10, double column_deg = 0.2)
      : id(tag_id) {
    const AprilTagImage print = render_apriltag("tag36h11", id);
    const double cell = size / print.width_at_border;
    const double half_print = 0.5 * cell * print.total_width;
    ImageGeometry& g = image.geometry;
    g.res_h = column_deg * kDeg;
    g.width = 200;
    g.u0 = 100;
    g.height = rings;
    for (int r = 0; r < rings; ++r)
      g.row_elevation.push_back((0.5 * (rings - 1) - r) * ring_deg * kDeg);
    g.res_v = ring_deg * kDeg;
    image.intensity = cv::Mat(g.height, g.width, CV_32F, cv::Scalar(50));  // grey wall
    image.mask = cv::Mat(g.height, g.width, CV_8U, cv::Scalar(255));
    for (int row = 0; row < g.height; ++row)
      for (int col = 0; col < g.width; ++col) {
        const Vec3 ray = g.ray(col, row);
        const Vec3 p = ray * (distance / ray.x());
        // Printed cell: columns left to right (-y), rows top to bottom (-z).
        const double x = (half_print - p.y()) / cell, y = (half_print - (p.z() - z0)) / cell;
        if (x < 0 || y < 0 || x >= print.total_width || y >= print.total_width) continue;
        const int cx = static_cast<int>(x), cy = static_cast<int>(y);
        image.intensity.at<float>(row, col) = static_cast<float>(
            print.pixels[static_cast<std::size_t>(cy) * print.total_width + cx] ? white : black);
      }
    const double h = 0.5 * size;
    const Vec3 tl(distance, h, z0 + h), tr(distance, -h, z0 + h), br(distance, -h, z0 - h),
        bl(distance, h, z0 - h);
    corners = {g.pixel_of_point(tl), g.pixel_of_point(tr), g.pixel_of_point(br),
               g.pixel_of_point(bl)};
  }
};

int popcount(std::uint64_t x) { return static_cast<int>(std::bitset<64>(x).count()); }

TEST(RingCellReader, DenseRingsReadEveryCellRight) {
  // 1 m tag at 2 m, 0.4 deg rings: 3.5 rings per cell.
  const RingScene scene(42, 1.0, 2.0, 90, 0.4, 0.0);
  const auto book = CellCodeBook::for_family("apriltag:tag36h11");
  const MarkerSamples samples(scene.corners, scene.image, scene.image.intensity, *book);
  ASSERT_FALSE(samples.empty());
  std::vector<MarkerSamples::Placed> placed;
  samples.place(0, 0, placed);
  const CellReading cells = read_cells(placed, *book, CellReadOptions{});
  EXPECT_TRUE(cells.levels_ok);
  EXPECT_NEAR(cells.black, 10, 1e-6);
  EXPECT_NEAR(cells.white, 100, 1e-6);
  EXPECT_EQ(cells.fixed_agreeing, cells.fixed_cells);
  EXPECT_EQ(cells.bits.known, (std::uint64_t{1} << 36) - 1);
  EXPECT_EQ(cells.bits.white, book->code(42, 0));
}

TEST(RingCellReader, SparseRingsLeaveErasuresAndNoErrors) {
  // 1 m tag at 4.5 m on VLP-16-like 2 deg rings: 0.8 rings per cell row.
  const RingScene scene(42, 1.0, 4.5, 16, 2.0, 0.03);
  const auto book = CellCodeBook::for_family("apriltag:tag36h11");
  const MarkerSamples samples(scene.corners, scene.image, scene.image.intensity, *book);
  std::vector<MarkerSamples::Placed> placed;
  samples.place(0, 0, placed);
  const CellReading cells = read_cells(placed, *book, CellReadOptions{});
  EXPECT_TRUE(cells.levels_ok);
  const int known = popcount(cells.bits.known);
  EXPECT_GT(known, 0);
  EXPECT_LT(known, 36);     // some cell rows no ring crossed near their middle
  EXPECT_EQ(known % 6, 0);  // whole cell rows: a ring reads all six cells of its row
  EXPECT_EQ((cells.bits.white ^ book->code(42, 0)) & cells.bits.known, 0u);
}

TEST(RingDecoder, ConfirmsCorrectsAndContradicts) {
  const RingScene scene(42, 1.0, 2.0, 90, 0.4, 0.0);
  const RingDecoder decoder({"apriltag:tag36h11"}, RingDecodeSettings{});
  ASSERT_TRUE(decoder.supports("apriltag:tag36h11"));
  EXPECT_FALSE(decoder.supports("aruco:DICT_4X4_50"));
  const std::vector<Vec2> truth(scene.corners.begin(), scene.corners.end());

  Detection right{"apriltag:tag36h11", 42, truth, {}, {}, 0, 0};
  EXPECT_EQ(decoder.verify(right, scene.image, scene.image.intensity), RingVerdict::kConfirmed);

  // Corners starting at the top-right: the samples name the turn, and the order is restored.
  Detection turned = right;
  std::rotate(turned.corners_px.begin(), turned.corners_px.begin() + 1, turned.corners_px.end());
  EXPECT_EQ(decoder.verify(turned, scene.image, scene.image.intensity), RingVerdict::kCorrected);
  EXPECT_EQ(turned.id, 42);
  for (int k = 0; k < 4; ++k) EXPECT_LT((turned.corners_px[k] - truth[k]).norm(), 1e-12);

  // A wrong id that the samples decode safely is corrected.
  Detection wrong = right;
  wrong.id = 43;
  EXPECT_EQ(decoder.verify(wrong, scene.image, scene.image.intensity), RingVerdict::kCorrected);
  EXPECT_EQ(wrong.id, 42);

  // A blank square with a black border: the fixed cells read right, the data contradicts id 42.
  RingScene blank = scene;
  blank.image.intensity = scene.image.intensity.clone();
  for (int row = 0; row < blank.image.geometry.height; ++row)
    for (int col = 0; col < blank.image.geometry.width; ++col) {
      const Vec2 c = blank.corners[0], e = blank.corners[2];
      const double inset_u = 0.25 * (e.x() - c.x()), inset_v = 0.25 * (e.y() - c.y());
      if (col > c.x() + inset_u && col < e.x() - inset_u && row > c.y() + inset_v &&
          row < e.y() - inset_v)
        blank.image.intensity.at<float>(row, col) = 10;
    }
  Detection on_blank = right;
  EXPECT_EQ(decoder.verify(on_blank, blank.image, blank.image.intensity),
            RingVerdict::kContradicted);
}

TEST(RingDecoder, FindsTheVerticalShiftOfCornersOffByHalfARing) {
  // Far tag, corners moved down by 40 % of a ring spacing (where a square-pixel detector may put
  // them): the fixed cells pull the grid back, and the reading makes no error.
  const RingScene scene(7, 1.0, 3.5, 16, 2.0, 0.1);
  const RingDecoder decoder({"apriltag:tag36h11"}, RingDecodeSettings{});
  std::array<Vec2, 4> off = scene.corners;
  for (Vec2& c : off) c.y() += 0.4;
  const RingRead r = decoder.read("apriltag:tag36h11", off, scene.image, scene.image.intensity);
  ASSERT_TRUE(r.read);
  const auto book = CellCodeBook::for_family("apriltag:tag36h11");
  EXPECT_EQ((r.cells.bits.white ^ book->code(7, 0)) & r.cells.bits.known, 0u);
  EXPECT_GT(popcount(r.cells.bits.known), 0);
  EXPECT_LT(r.shift_top, 0);  // moved back up
}

// Where the columns are the coarse axis (an OS2-128 at 1024 columns: 0.35 deg columns, 0.177 deg
// rings), the placings move the sides along the rows: corners 0.4 column right of a 17 cm tag at
// 3.8 m (0.9 column a cell) are pulled back left, and the reading makes no error.
TEST(RingDecoder, FindsTheHorizontalShiftWhereColumnsAreCoarse) {
  const RingScene scene(7, 0.172, 3.8, 48, 0.177, 0.0, 100, 10, 0.3516);
  EXPECT_TRUE(columns_are_coarse(scene.image.geometry));
  const RingDecoder decoder({"apriltag:tag36h11"}, RingDecodeSettings{});
  const auto book = CellCodeBook::for_family("apriltag:tag36h11");
  // Read as a ring candidate (the cells' middle 90 %): at 0.9 columns a cell a detection's middle
  // 60 % leaves most cells without a sample.
  const RingRead exact =
      decoder.read("apriltag:tag36h11", scene.corners, scene.image, scene.image.intensity, true);
  ASSERT_TRUE(exact.read);
  EXPECT_TRUE(exact.decoded.accepted);
  EXPECT_EQ(exact.decoded.id, 7);
  std::array<Vec2, 4> off = scene.corners;
  for (Vec2& c : off) c.x() += 0.4;
  const RingRead r =
      decoder.read("apriltag:tag36h11", off, scene.image, scene.image.intensity, true);
  ASSERT_TRUE(r.read);
  EXPECT_EQ((r.cells.bits.white ^ book->code(7, 0)) & r.cells.bits.known, 0u);
  EXPECT_GE(popcount(r.cells.bits.known), 24);
  // Measured: 24 bits known and read right, 8.6 chance-match bits at the placing chosen (a
  // candidate wants 12 and is read again with its sides moved; exact corners read 30 bits).
  EXPECT_EQ(r.decoded.id, 7);
  EXPECT_EQ(r.decoded.errors, 0);
  // Pulled back left: the corners it reports lie nearer the true ones than those given.
  for (std::size_t k = 0; k < 4; ++k)
    EXPECT_LT(std::abs(r.corners_px[k].x() - scene.corners[k].x()), 0.25) << "corner " << k;
}

TEST(RingDecoder, ColumnsAreCoarseOnlyWhereMuchCoarserThanTheRows) {
  const auto geometry = [](double column_deg, double ring_deg) {
    ImageGeometry g;
    g.res_h = column_deg * kDeg;
    g.width = 100;
    g.height = 16;
    for (int r = 0; r < g.height; ++r) g.row_elevation.push_back((7.5 - r) * ring_deg * kDeg);
    g.res_v = ring_deg * kDeg;
    return g;
  };
  EXPECT_TRUE(columns_are_coarse(geometry(0.3516, 0.1772)));   // OS2-128, 1024 columns
  EXPECT_FALSE(columns_are_coarse(geometry(0.3516, 0.3571)));  // OS2-64
  EXPECT_FALSE(columns_are_coarse(geometry(0.2, 2.0)));        // VLP-16
}

// The corners as given (variant 0), off by part of a pixel and listed from the top-right corner
// (1), or with two corners moved by pixels, a quad that is no affine image of a square (2).
std::array<Vec2, 4> corners_variant(std::array<Vec2, 4> corners, int variant) {
  if (variant == 1) {
    for (Vec2& c : corners) c += Vec2(0.3, -0.2);
    std::rotate(corners.begin(), corners.begin() + 1, corners.end());
  } else if (variant == 2) {
    corners[1] += Vec2(3.0, 1.0);
    corners[3] += Vec2(-1.0, -0.5);
  }
  return corners;
}

// The samples kept for a detection's search give every whole-square shift in the range the
// agreement all samples give, from far fewer samples: dense and sparse rings, corners off by
// part of a pixel, the quad's corners listed from another one, three ranges (one of a single
// shift) and two central fractions.
TEST(MarkerSamples, FixedCellSamplesGiveTheAgreementOfAllSamples) {
  const auto book = CellCodeBook::for_family("apriltag:tag36h11");
  const RingScene dense(42, 1.0, 2.0, 90, 0.4, 0.0), sparse(7, 1.0, 3.5, 16, 2.0, 0.05);
  int placings = 0;
  for (const RingScene* scene : {&dense, &sparse}) {
    for (int variant = 0; variant < 2; ++variant) {
      const std::array<Vec2, 4> corners = corners_variant(scene->corners, variant);
      const MarkerSamples all(corners, scene->image, scene->image.intensity, *book);
      ASSERT_FALSE(all.empty());
      for (const auto& [reach, step, central] :
           {std::tuple{0.6, 0.05, 0.6}, std::tuple{1.5, 0.1, 0.9}, std::tuple{0.0, 0.1, 0.6}}) {
        CellReadOptions options;
        options.central_fraction = central;
        const MarkerSamples kept = all.fixed_cell_samples(-reach, reach, *book, central);
        EXPECT_LT(kept.size(), all.size() * 7 / 10) << "kept too many to gain anything";
        MarkerSamples::Scratch scratch;
        for (double shift = -reach; shift <= reach + 1e-9; shift += step) {
          const double expected = all.fixed_agreement(shift, shift, *book, options, scratch);
          EXPECT_EQ(kept.fixed_agreement(shift, shift, *book, options, scratch), expected)
              << "shift " << shift << ", variant " << variant;
          placings += expected >= 0 ? 1 : 0;
        }
      }
    }
  }
  EXPECT_GT(placings, 40) << "too few placings read: the test checks too little";
}

// The same for the ring candidates' search, which moves the top and bottom sides independently:
// every placing of both ranges gets the agreement of all samples from the samples kept, also for
// a quad that is no affine image of a square (two corners moved by pixels).
TEST(MarkerSamples, FixedCellSamplesOfIndependentSidesGiveTheAgreementOfAllSamples) {
  const auto book = CellCodeBook::for_family("apriltag:tag36h11");
  const RingScene dense(42, 1.0, 2.0, 90, 0.4, 0.0), sparse(7, 1.0, 3.5, 16, 2.0, 0.05);
  int placings = 0;
  std::size_t kept_total = 0, all_total = 0;
  for (const RingScene* scene : {&dense, &sparse}) {
    for (int variant = 0; variant < 3; ++variant) {
      const std::array<Vec2, 4> corners = corners_variant(scene->corners, variant);
      const MarkerSamples all(corners, scene->image, scene->image.intensity, *book);
      ASSERT_FALSE(all.empty());
      for (const auto& [top_low, top_high, bottom_low, bottom_high, step, central] :
           {std::tuple{-1.5, 0.6, -0.6, 1.5, 0.1, 0.9},
            std::tuple{-0.6, 0.6, -0.6, 0.6, 0.2, 0.6}}) {
        CellReadOptions options;
        options.central_fraction = central;
        const MarkerSamples kept =
            all.fixed_cell_samples({top_low, top_high}, {bottom_low, bottom_high}, *book, central);
        kept_total += kept.size();
        all_total += all.size();
        MarkerSamples::Scratch scratch;
        for (double top = top_low; top <= top_high + 1e-9; top += step) {
          for (double bottom = bottom_low; bottom <= bottom_high + 1e-9; bottom += step) {
            const double expected = all.fixed_agreement(top, bottom, *book, options, scratch);
            ASSERT_EQ(kept.fixed_agreement(top, bottom, *book, options, scratch), expected)
                << "top " << top << ", bottom " << bottom << ", variant " << variant;
            placings += expected >= 0 ? 1 : 0;
          }
        }
      }
    }
  }
  EXPECT_GT(placings, 200) << "too few placings read: the test checks too little";
  EXPECT_LT(kept_total, all_total * 8 / 10) << "kept too many to gain anything";
}

// The vectorised read of one placing, which the candidates' tied placings use, gives what
// read_cells gives on place()'s samples: levels, fixed cells and bits, at independent top and
// bottom shifts over dense and sparse rings and both central fractions.
TEST(MarkerSamples, ReadGivesWhatReadCellsGivesOnThePlacedSamples) {
  const auto book = CellCodeBook::for_family("apriltag:tag36h11");
  const RingScene dense(42, 1.0, 2.0, 90, 0.4, 0.0), sparse(7, 1.0, 3.5, 16, 2.0, 0.05);
  int compared = 0, with_bits = 0;
  for (const RingScene* scene : {&dense, &sparse}) {
    const MarkerSamples samples(scene->corners, scene->image, scene->image.intensity, *book);
    ASSERT_FALSE(samples.empty());
    for (const double central : {0.6, 0.9}) {
      CellReadOptions options;
      options.central_fraction = central;
      MarkerSamples::Scratch scratch;
      std::vector<MarkerSamples::Placed> placed;
      for (int t = 0; t < 8; ++t) {
        for (int b = 0; b < 8; ++b) {
          const double top = -0.6 + 0.3 * t, bottom = -1.5 + 0.3 * b;
          samples.place(top, bottom, placed);
          const CellReading expected = read_cells(placed, *book, options);
          const CellReading got = samples.read(top, bottom, *book, options, scratch);
          SCOPED_TRACE(::testing::Message() << "top " << top << " bottom " << bottom);
          EXPECT_EQ(got.levels_ok, expected.levels_ok);
          EXPECT_EQ(got.black, expected.black);
          EXPECT_EQ(got.white, expected.white);
          EXPECT_EQ(got.fixed_cells, expected.fixed_cells);
          EXPECT_EQ(got.fixed_agreeing, expected.fixed_agreeing);
          EXPECT_EQ(got.bits.known, expected.bits.known);
          EXPECT_EQ(got.bits.white, expected.bits.white);
          ++compared;
          with_bits += expected.bits.known != 0 ? 1 : 0;
        }
      }
    }
  }
  EXPECT_EQ(compared, 2 * 2 * 8 * 8);
  EXPECT_GT(with_bits, compared / 2) << "too few placings read bits: the test checks too little";
}

}  // namespace
}  // namespace iilfm::detail
