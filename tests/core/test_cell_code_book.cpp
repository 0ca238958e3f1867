// The marker families as cell grids, and decoding with erased bits.
#include <gtest/gtest.h>

#include <bitset>
#include <numeric>
#include <opencv2/aruco.hpp>
#include <optional>
#include <random>

#include "../../src/cell_code_book.hpp"
#include "../../src/ring_decoding.hpp"
#include "iilfm/apriltag_families.hpp"
#include "iilfm/detector.hpp"
#include "iilfm/error.hpp"

namespace iilfm::detail {
namespace {

int popcount(std::uint64_t x) { return static_cast<int>(std::bitset<64>(x).count()); }

// The data bits of a printed image (0 = black), its pixels turned `quarter_turns` clockwise.
std::uint64_t bits_of_print(const CellCodeBook& book, const std::vector<std::uint8_t>& pixels,
                            int quarter_turns) {
  const int T = book.total_width();
  std::vector<std::uint8_t> turned = pixels;
  for (int q = 0; q < quarter_turns; ++q) {
    std::vector<std::uint8_t> next(turned.size());
    // Clockwise: (x, y) -> (T - 1 - y, x).
    for (int y = 0; y < T; ++y)
      for (int x = 0; x < T; ++x) next[x * T + (T - 1 - y)] = turned[y * T + x];
    turned = next;
  }
  std::uint64_t bits = 0;
  for (int y = 0; y < T; ++y)
    for (int x = 0; x < T; ++x) {
      const int role = book.cell_role(x, y);
      if (role >= 0 && turned[y * T + x]) bits |= std::uint64_t{1} << role;
    }
  return bits;
}

TEST(CellCodeBook, AprilTagBookMatchesLibapriltagsPrintInEveryTurn) {
  const auto book = CellCodeBook::for_family("apriltag:tag36h11");
  ASSERT_TRUE(book);
  EXPECT_EQ(book->total_width(), 10);
  EXPECT_EQ(book->border_width(), 8);
  EXPECT_EQ(book->bits(), 36);
  EXPECT_EQ(book->codes(), 587);
  EXPECT_EQ(book->min_distance(), 11);
  // Border ring black, margin white.
  EXPECT_EQ(book->cell_role(1, 1), CellCodeBook::kFixedBlack);
  EXPECT_EQ(book->cell_role(8, 4), CellCodeBook::kFixedBlack);
  EXPECT_EQ(book->cell_role(0, 5), CellCodeBook::kFixedWhite);
  for (int id : {0, 17, 586}) {
    const AprilTagImage print = render_apriltag("tag36h11", id);
    for (int q = 0; q < 4; ++q) EXPECT_EQ(book->code(id, q), bits_of_print(*book, print.pixels, q));
  }
}

TEST(CellCodeBook, ArucoBookMatchesDrawMarker) {
  const auto book = CellCodeBook::for_family("aruco:DICT_ARUCO_ORIGINAL");
  ASSERT_TRUE(book);
  EXPECT_EQ(book->total_width(), 9);
  EXPECT_EQ(book->border_width(), 7);
  EXPECT_EQ(book->bits(), 25);
  EXPECT_EQ(book->codes(), 1024);
  const auto dict = cv::aruco::getPredefinedDictionary(cv::aruco::DICT_ARUCO_ORIGINAL);
  for (int id : {0, 96, 100, 1023}) {
    cv::Mat drawn;
    cv::aruco::drawMarker(dict, id, 7, drawn, 1);  // one pixel per cell, black border
    cv::Mat print(9, 9, CV_8U, cv::Scalar(255));
    drawn.copyTo(print(cv::Rect(1, 1, 7, 7)));
    const std::vector<std::uint8_t> pixels(print.begin<std::uint8_t>(), print.end<std::uint8_t>());
    for (int q = 0; q < 4; ++q) EXPECT_EQ(book->code(id, q), bits_of_print(*book, pixels, q));
  }
  EXPECT_EQ(CellCodeBook::for_family("rings:ring9h3"), nullptr);
}

BitReading all_known(std::uint64_t white, int bits) {
  return {white, bits == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << bits) - 1};
}

TEST(DecodeCells, FindsEveryIdAndTurnFromCleanReadings) {
  const auto book = CellCodeBook::for_family("apriltag:tag36h11");
  for (int id : {0, 100, 586})
    for (int q = 0; q < 4; ++q) {
      const DecodeResult r = decode_cells(*book, all_known(book->code(id, q), 36), DecodeLimits{});
      EXPECT_TRUE(r.accepted);
      EXPECT_EQ(r.id, id);
      EXPECT_EQ(r.quarter_turns, q);
      EXPECT_EQ(r.errors, 0);
      EXPECT_EQ(r.erasures, 0);
      EXPECT_GE(r.distance_to_next, 11);
      EXPECT_NEAR(r.security_bits, 36 - std::log2(4.0 * 587), 1e-9);
    }
}

TEST(DecodeCells, CorrectsErrorsAmongErasures) {
  const auto book = CellCodeBook::for_family("apriltag:tag36h11");
  DecodeLimits limits;
  limits.max_errors = 5;
  std::mt19937 rng(3);
  int accepted = 0, thin_accepted = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const int id = static_cast<int>(rng() % 587), q = static_cast<int>(rng() % 4);
    std::vector<int> order(36);
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);
    // One cell row unsampled (6 erasures) and one misread bit: 30 known bits.
    BitReading r = all_known(book->code(id, q), 36);
    for (int k = 0; k < 6; ++k) r.known &= ~(std::uint64_t{1} << order[k]);
    r.white ^= std::uint64_t{1} << order[6];
    const DecodeResult d = decode_cells(*book, r, limits);
    EXPECT_EQ(d.erasures, 6);
    EXPECT_EQ(d.errors, 1);
    EXPECT_EQ(d.id, id);
    EXPECT_EQ(d.quarter_turns, q);
    // 2 t + 2 <= distance_to_next holds unless the erasures hit the bits that told the nearest
    // code apart; a random 30-bit reading is within 1 bit of some code 1 time in 14,000.
    EXPECT_NEAR(d.security_bits, 30 - std::log2(4.0 * 587) - std::log2(31.0), 1e-9);
    accepted += d.accepted;
    // Two rows unsampled and two misread bits still name the id, but a random 24-bit reading
    // comes that close to some code 1 time in 24: refused.
    BitReading thin = r;
    for (int k = 7; k < 13; ++k) thin.known &= ~(std::uint64_t{1} << order[k]);
    thin.white ^= std::uint64_t{1} << order[13];
    const DecodeResult t = decode_cells(*book, thin, limits);
    EXPECT_EQ(t.id, id);
    EXPECT_EQ(t.errors, 2);
    thin_accepted += t.accepted;
  }
  EXPECT_GE(accepted, 45);
  EXPECT_EQ(thin_accepted, 0);
}

TEST(DecodeCells, RefusesReadingsTooThinToBeSafe) {
  const auto book = CellCodeBook::for_family("apriltag:tag36h11");
  BitReading r = all_known(book->code(42, 0), 36);
  r.known = (std::uint64_t{1} << 16) - 1;  // 16 known bits: 4 x 587 codes match 1 in 28 by chance
  const DecodeResult d = decode_cells(*book, r, DecodeLimits{});
  EXPECT_EQ(d.errors, 0);
  EXPECT_LT(d.security_bits, 10);
  EXPECT_FALSE(d.accepted);
  // Random readings of 36 bits lie several bits from every code: refused.
  std::mt19937_64 rng(7);
  DecodeLimits limits;
  limits.max_errors = 5;
  for (int trial = 0; trial < 100; ++trial)
    EXPECT_FALSE(decode_cells(*book, all_known(rng() & ((std::uint64_t{1} << 36) - 1), 36), limits)
                     .accepted);
}

TEST(DecodeCells, RefusesReadingsHalfwayBetweenTwoCodes) {
  const auto book = CellCodeBook::for_family("apriltag:tag16h5");
  ASSERT_EQ(book->min_distance(), 5);
  // Two codes 5 bits apart (tag16h5's distance); a reading with 2 of those bits from the second.
  int a = -1, b = -1, qb = 0;
  for (int i = 0; i < book->codes() && a < 0; ++i)
    for (int j = 0; j < book->codes() && a < 0; ++j)
      for (int q = 0; q < 4 && a < 0; ++q)
        if ((i != j || q != 0) && popcount(book->code(i, 0) ^ book->code(j, q)) == 5) {
          a = i;
          b = j;
          qb = q;
        }
  ASSERT_GE(a, 0);
  const std::uint64_t differ = book->code(a, 0) ^ book->code(b, qb);
  std::uint64_t two = 0;
  for (int k = 0, taken = 0; k < 16 && taken < 2; ++k)
    if ((differ >> k) & 1u) {
      two |= std::uint64_t{1} << k;
      ++taken;
    }
  DecodeLimits limits;
  limits.max_errors = 2;
  const DecodeResult d = decode_cells(*book, all_known(book->code(a, 0) ^ two, 16), limits);
  EXPECT_EQ(d.id, a);
  EXPECT_EQ(d.errors, 2);
  EXPECT_EQ(d.distance_to_next, 5);
  EXPECT_FALSE(d.accepted);  // 2 * 2 + 2 > 5
  limits.min_distance_margin = 1;
  EXPECT_TRUE(decode_cells(*book, all_known(book->code(a, 0) ^ two, 16), limits).accepted ||
              decode_cells(*book, all_known(book->code(a, 0) ^ two, 16), limits).security_bits <
                  limits.min_security_bits);
}

TEST(DecodeCells, ErrorsAgainstCountsKnownBitsOnly) {
  const auto book = CellCodeBook::for_family("aruco:DICT_4X4_50");
  BitReading r = all_known(book->code(7, 0), 16);
  EXPECT_EQ(errors_against(*book, r, 7), 0);
  r.white ^= 0b101;
  EXPECT_EQ(errors_against(*book, r, 7), 2);
  r.known &= ~std::uint64_t{1};
  EXPECT_EQ(errors_against(*book, r, 7), 1);
  EXPECT_EQ(errors_against(*book, r, 8), popcount((book->code(8, 0) ^ r.white) & r.known));
}

// A book of some ids alone numbers its codes in the order given and reports their ids; a
// reading too thin for the whole family is safe among a few codes.
TEST(CellCodeBook, ARestrictedBookDecodesItsIdsWithFewerChancesOfAMatch) {
  const auto book = CellCodeBook::for_family("apriltag:tag36h11");
  const CellCodeBook few = book->restricted_to({17, 5, 17});
  ASSERT_EQ(few.codes(), 2);  // the repeated id once
  EXPECT_EQ(few.id_at(0), 17);
  EXPECT_EQ(few.id_at(1), 5);
  EXPECT_EQ(few.code(0, 2), book->code(17, 2));
  EXPECT_EQ(few.border_width(), book->border_width());
  BitReading r = all_known(book->code(5, 3), 36);
  r.known = (std::uint64_t{1} << 16) - 1;  // 16 known bits
  const DecodeResult all = decode_cells(*book, r, DecodeLimits{});
  EXPECT_FALSE(all.accepted);  // 16 - log2(4 x 587) = 4.8 bits
  const DecodeResult among_few = decode_cells(few, r, DecodeLimits{});
  EXPECT_TRUE(among_few.accepted);
  EXPECT_EQ(among_few.id, 5);
  EXPECT_EQ(among_few.quarter_turns, 3);
  EXPECT_NEAR(among_few.security_bits, 16 - std::log2(4.0 * 2), 1e-9);
  EXPECT_THROW(book->restricted_to({0, 587}), InputError);
  EXPECT_THROW(book->restricted_to({-1}), InputError);
}

// tag36h11's books with id 17 known.
FamilyCodeBooks books_knowing_17() {
  FamilyCodeBooks books;
  books.all = CellCodeBook::for_family("apriltag:tag36h11");
  books.known = std::make_unique<CellCodeBook>(books.all->restricted_to({17}));
  return books;
}

// Limits that tolerate up to 5 misread bits.
DecodeLimits five_errors() {
  DecodeLimits limits;
  limits.max_errors = 5;
  return limits;
}

// The ids known to be in a scene (a map's, `--ids`) decode from fewer bits, but only where the
// family's nearest code is the known one, clearly: a marker of another id is not taken for it.
TEST(FamilyCodeBooks, AKnownIdIsReadFromFewerBitsUnlessAnotherCodeIsNearer) {
  const FamilyCodeBooks books = books_knowing_17();
  const DecodeLimits limits = five_errors();
  // The last 20 bits of id 17 read right: 20 - log2(4 x 587) = 8.8 bits for the family, 18 for
  // one id.
  BitReading r = all_known(books.all->code(17, 1), 36);
  r.known = ((std::uint64_t{1} << 20) - 1) << 16;
  const DecodeResult for_family = decode_cells(*books.all, r, limits);
  ASSERT_FALSE(for_family.accepted);
  ASSERT_GE(for_family.distance_to_next, 3);  // 2 x 0 errors + margin 2, and a bit more
  DecodeResult d = books.decode(r, limits);
  EXPECT_TRUE(d.accepted);
  EXPECT_EQ(d.id, 17);
  EXPECT_EQ(d.quarter_turns, 1);
  EXPECT_NEAR(d.security_bits, 20 - std::log2(4.0), 1e-9);
  // Id 300 read on 18 bits where it and id 17 agree and 2 where they differ: no error against
  // 300, 2 against 17, which among the known codes alone would decode (20 - 2 - log2 211 = 10.3
  // bits).
  const std::uint64_t code17 = books.all->code(17, 0), code300 = books.all->code(300, 0);
  BitReading other{code300, 0};
  int agreeing = 0, differing = 0;
  for (int k = 0; k < 36; ++k) {
    const bool same = ((code17 ^ code300) >> k & 1u) == 0;
    if (same ? agreeing++ < 18 : differing++ < 2) other.known |= std::uint64_t{1} << k;
  }
  ASSERT_EQ(popcount(other.known), 20);
  ASSERT_EQ(decode_cells(*books.all, other, limits).id, 300);
  ASSERT_EQ(errors_against(*books.all, other, 17), 2);
  ASSERT_TRUE(decode_cells(*books.known, other, limits).accepted);
  d = books.decode(other, limits);
  EXPECT_FALSE(d.accepted && d.id == 17);
}

// A known id the family's limits accept already is counted among the known codes too: a ring
// candidate asks for more chance-match bits (12) than the limits (10).
TEST(FamilyCodeBooks, AKnownIdTheFamilyAcceptsIsCountedAmongTheKnownCodes) {
  const FamilyCodeBooks books = books_knowing_17();
  const DecodeLimits limits = five_errors();
  // 24 bits of id 17 read right: 24 - log2(4 x 587) = 12.8 bits for the family, 22 for one id.
  BitReading r = all_known(books.all->code(17, 0), 36);
  r.known = (std::uint64_t{1} << 24) - 1;
  const DecodeResult for_family = decode_cells(*books.all, r, limits);
  ASSERT_TRUE(for_family.accepted);
  ASSERT_GE(for_family.distance_to_next, 3);
  const DecodeResult d = books.decode(r, limits);
  EXPECT_TRUE(d.accepted);
  EXPECT_EQ(d.id, 17);
  EXPECT_NEAR(d.security_bits, 24 - std::log2(4.0), 1e-9);
  // An id not known keeps the family's decoding.
  const BitReading other = [&] {
    BitReading o = all_known(books.all->code(300, 0), 36);
    o.known = r.known;
    return o;
  }();
  const DecodeResult d300 = books.decode(other, limits);
  EXPECT_EQ(d300.id, 300);
  EXPECT_NEAR(d300.security_bits, decode_cells(*books.all, other, limits).security_bits, 1e-9);
}

// Id 17 read on 20 bits, 20-`apart` of them where another code agrees with it and `apart` where it
// does not, then `errors` of the agreeing ones misread: the reading lies `errors` bits from id 17
// and `apart` + `errors` from that code, the next nearest.
std::optional<BitReading> reading_apart_from_another_code(const CellCodeBook& book, int apart,
                                                          int errors = 0) {
  const std::uint64_t code17 = book.code(17, 0);
  DecodeLimits limits;
  limits.max_errors = 5;
  for (int other = 0; other < book.codes(); ++other) {
    if (other == 17) continue;
    BitReading r{code17, 0};
    int agreeing = 0, differing = 0;
    for (int k = 0; k < 36; ++k) {
      const bool same = ((code17 ^ book.code(other, 0)) >> k & 1u) == 0;
      const std::uint64_t bit = std::uint64_t{1} << k;
      if (same ? agreeing++ < 20 - apart : differing++ < apart) r.known |= bit;
      if (same && agreeing <= errors) r.white ^= bit;  // misread
    }
    const DecodeResult d = decode_cells(book, r, limits);
    if (popcount(r.known) == 20 && d.id == 17 && d.errors == errors &&
        d.reading_to_next == apart + errors)
      return r;
  }
  return std::nullopt;
}

// A marker of an id not known must misread three bits to pass for a known one: a reading two bits
// from another code is decoded over the whole family only (one wrong id in the partial-map test of
// docs/pipeline.md came from such a reading), one three bits away over the known codes.
TEST(FamilyCodeBooks, AKnownIdIsReadFromFewerBitsOnlyThreeBitsFromEveryOtherCode) {
  const FamilyCodeBooks books = books_knowing_17();
  const DecodeLimits limits = five_errors();
  const std::optional<BitReading> two = reading_apart_from_another_code(*books.all, 2);
  const std::optional<BitReading> three = reading_apart_from_another_code(*books.all, 3);
  ASSERT_TRUE(two && three);
  for (const BitReading& r : {*two, *three}) {
    ASSERT_FALSE(decode_cells(*books.all, r, limits).accepted);  // 8.8 chance-match bits
    ASSERT_TRUE(decode_cells(*books.known, r, limits).accepted);
  }
  EXPECT_FALSE(books.decode(*two, limits).accepted);
  const DecodeResult d = books.decode(*three, limits);
  EXPECT_TRUE(d.accepted);
  EXPECT_EQ(d.id, 17);
}

// With errors, the same three bits more: a reading one bit from the known id and four from every
// other code is read among the known codes (an OS1-64's 40 cm tag at 5 m, one error in 22 bits),
// one only three bits from another code is not. The code four bits from the reading lies three
// from the known one here, and asking the worst case of one error for (2 t + 3 to the nearest
// code, five) refused both.
TEST(FamilyCodeBooks, AKnownIdReadWithErrorsNeedsThreeBitsMoreToEveryOtherCode) {
  const FamilyCodeBooks books = books_knowing_17();
  const DecodeLimits limits = five_errors();
  const std::optional<BitReading> clear = reading_apart_from_another_code(*books.all, 3, 1);
  const std::optional<BitReading> near = reading_apart_from_another_code(*books.all, 2, 1);
  ASSERT_TRUE(clear && near);
  for (const BitReading& r : {*clear, *near}) {
    ASSERT_FALSE(decode_cells(*books.all, r, limits).accepted);
    ASSERT_TRUE(decode_cells(*books.known, r, limits).accepted);  // 20 - 2 - log2 21 = 13.6 bits
  }
  const DecodeResult d = books.decode(*clear, limits);
  EXPECT_TRUE(d.accepted);
  EXPECT_EQ(d.id, 17);
  EXPECT_EQ(d.errors, 1);
  EXPECT_NEAR(d.security_bits, 20 - std::log2(4.0) - std::log2(21.0), 1e-9);
  EXPECT_FALSE(books.decode(*near, limits).accepted);
}

}  // namespace
}  // namespace iilfm::detail

namespace iilfm::detail {
namespace {

// Every AprilTag and ArUco family gets a book (the pipeline builds one per family asked for),
// with its codes unchanged by four quarter turns.
TEST(CellCodeBook, EverySquareFamilyHasABook) {
  int books = 0;
  for (const std::string& family : known_families()) {
    if (family.rfind("apriltag:", 0) != 0 && family.rfind("aruco:", 0) != 0) continue;
    const auto book = CellCodeBook::for_family(family);
    ASSERT_TRUE(book) << family;
    EXPECT_EQ(book->border_width(), family_layout(family).border_width) << family;
    EXPECT_GT(book->bits(), 0) << family;
    ++books;
  }
  EXPECT_EQ(books, 9 + 21);
}

}  // namespace
}  // namespace iilfm::detail
