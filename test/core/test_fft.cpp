#include <fftw3.h>
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <thread>

#include "room_reverb/audio/convolution.h"
#include "room_reverb/audio/fft.h"
#include "synthetic_rir.h"

using namespace room_reverb::core;

TEST(Fft, NextFastSizeHasOnlySmallFactors) {
  EXPECT_EQ(nextFastFftSize(1), 1u);
  EXPECT_EQ(nextFastFftSize(1000), 1000u);
  EXPECT_EQ(nextFastFftSize(1009), 1024u);  // 1009 is prime
  EXPECT_EQ(nextFastFftSize(11), 12u);
}

TEST(Fft, ForwardMatchesDirectDft) {
  for (std::size_t n : {1u, 7u, 64u, 100u}) {
    const std::vector<float> x = room_reverb::test::whiteNoise(n, 3);
    RealFft fft(n);
    const auto spectrum = fft.forward(x);
    for (std::size_t k = 0; k < fft.spectrumSize(); ++k) {
      std::complex<double> sum = 0.0;
      for (std::size_t t = 0; t < n; ++t) sum += static_cast<double>(x[t]) * std::polar(1.0, -2 * M_PI * k * t / n);
      EXPECT_NEAR(spectrum[k].real(), sum.real(), 1e-4 * std::sqrt(n)) << n << " " << k;
      EXPECT_NEAR(spectrum[k].imag(), sum.imag(), 1e-4 * std::sqrt(n)) << n << " " << k;
    }
  }
}

TEST(Fft, InverseUndoesForward) {
  const std::vector<float> x = room_reverb::test::whiteNoise(960, 4);
  RealFft fft(960);
  const auto back = fft.inverse(fft.forward(x));
  for (std::size_t t = 0; t < x.size(); ++t) EXPECT_NEAR(back[t], x[t], 1e-5);
}

TEST(Fft, ComplexInverseMatchesDirectDft) {
  for (std::size_t n : {1u, 7u, 64u, 100u}) {
    const std::vector<float> re = room_reverb::test::whiteNoise(n, 6), im = room_reverb::test::whiteNoise(n, 7);
    std::vector<std::complex<float>> spectrum(n), time(n);
    for (std::size_t k = 0; k < n; ++k) spectrum[k] = {re[k], im[k]};
    ComplexInverseFft fft(n);
    fft.inverse(spectrum.data(), time.data());
    for (std::size_t t = 0; t < n; ++t) {
      std::complex<double> sum = 0.0;
      for (std::size_t k = 0; k < n; ++k) sum += std::complex<double>(spectrum[k]) * std::polar(1.0, 2 * M_PI * k * t / n);
      EXPECT_NEAR(time[t].real(), sum.real(), 1e-4 * std::sqrt(n)) << n << " " << t;
      EXPECT_NEAR(time[t].imag(), sum.imag(), 1e-4 * std::sqrt(n)) << n << " " << t;
    }
  }
  EXPECT_THROW(ComplexInverseFft(0), std::invalid_argument);
}

TEST(Fft, PlansAreSharedAcrossThreads) {
  // Many transforms of one size on several threads give the same answer as one.
  const std::vector<float> x = room_reverb::test::whiteNoise(4096, 5);
  RealFft reference(4096);
  const auto expected = reference.forward(x);
  std::vector<std::thread> threads;
  std::vector<int> mismatches(4, 0);
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < 50; ++i) {
        RealFft fft(4096);
        if (fft.forward(x) != expected) ++mismatches[t];
      }
    });
  }
  for (auto& thread : threads) thread.join();
  for (int m : mismatches) EXPECT_EQ(m, 0);
}

// Measured plans (FftPlanning::kMeasured): each test plans a size no other test uses, so
// that it is planned here and not taken from this process's cache.
std::string readAll(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(Fft, AMeasuredPlanTransformsAsTheEstimatedOneAndIsKept) {
  const std::string wisdom = ::testing::TempDir() + "room_reverb_fft_test/wisdom";
  std::filesystem::remove_all(::testing::TempDir() + "room_reverb_fft_test");
  setenv("ROOM_REVERB_FFTW_WISDOM", wisdom.c_str(), 1);
  const std::size_t n = 96;
  const std::vector<float> x = room_reverb::test::whiteNoise(n, 5);
  RealFft estimated(n), measured(n, FftPlanning::kMeasured);
  const auto a = estimated.forward(x), b = measured.forward(x);
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_LT(std::abs(a[k] - b[k]), 1e-4f) << k;
  const auto back = measured.inverse(b);
  for (std::size_t t = 0; t < n; ++t) EXPECT_NEAR(back[t], x[t], 1e-5f) << t;
  // Kept for the next process, in FFTW's own wisdom format.
  EXPECT_EQ(readAll(wisdom).rfind("(fftw-", 0), 0u);
  // Forgotten in this process, so that an estimated plan made later is the one any
  // process makes: FFTW holds no wisdom (its export names no codelet).
  char* held = fftwf_export_wisdom_to_string();
  ASSERT_NE(held, nullptr);
  EXPECT_EQ(std::string(held).find("codelet"), std::string::npos) << held;
  fftwf_free(held);
  unsetenv("ROOM_REVERB_FFTW_WISDOM");
}

// A stream measures its plans before its audio thread starts: the range's powers of two
// are measured (sizes no other test here uses) and kept on disk for the next process.
TEST(Fft, PreparedMeasuredPlansAreMeasuredAndKept) {
  const std::string wisdom = ::testing::TempDir() + "room_reverb_fft_prepare/wisdom";
  std::filesystem::remove_all(::testing::TempDir() + "room_reverb_fft_prepare");
  setenv("ROOM_REVERB_FFTW_WISDOM", wisdom.c_str(), 1);
  prepareMeasuredFftPlans(52, 208);  // 52, 104, 208
  EXPECT_EQ(readAll(wisdom).rfind("(fftw-", 0), 0u);
  // Made again, a prepared size comes from the shared cache and transforms as the
  // estimated plan does.
  const std::vector<float> x = room_reverb::test::whiteNoise(208, 3);
  RealFft estimated(208), measured(208, FftPlanning::kMeasured);
  const auto a = estimated.forward(x), b = measured.forward(x);
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_LT(std::abs(a[k] - b[k]), 1e-4f) << k;
  unsetenv("ROOM_REVERB_FFTW_WISDOM");
}

TEST(Fft, NowhereToKeepWisdomStillPlans) {
  // Empty: nothing kept; a directory that cannot be made: nothing kept, no error.
  for (const char* path : {"", "/proc/room_reverb_no_such_dir/wisdom"}) {
    setenv("ROOM_REVERB_FFTW_WISDOM", path, 1);
    const std::size_t n = std::string(path).empty() ? 192 : 224;
    RealFft fft(n, FftPlanning::kMeasured);
    const std::vector<float> x = room_reverb::test::whiteNoise(n, 7);
    const auto back = fft.inverse(fft.forward(x));
    for (std::size_t t = 0; t < n; ++t) EXPECT_NEAR(back[t], x[t], 1e-5f) << path << " " << t;
    EXPECT_FALSE(std::filesystem::exists("/proc/room_reverb_no_such_dir"));
  }
  unsetenv("ROOM_REVERB_FFTW_WISDOM");
}

TEST(Fft, DamagedWisdomIsMeasuredAgainAndReplaced) {
  // A wisdom file that is not FFTW's (a truncated copy, another program's file): the size
  // is measured afresh, transforms right, and the file holds FFTW's wisdom after.
  const std::string dir = ::testing::TempDir() + "room_reverb_fft_damaged";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string wisdom = dir + "/wisdom";
  for (const char* damage : {"(fftw-3.3.10 fftwf_wisdom #x9e7d4dee\n  (fftwf_codelet_r2cf_8 2", "not wisdom at all\n"}) {
    std::ofstream(wisdom) << damage;
    setenv("ROOM_REVERB_FFTW_WISDOM", wisdom.c_str(), 1);
    const std::size_t n = std::string(damage).front() == '(' ? 160 : 176;
    RealFft fft(n, FftPlanning::kMeasured);
    const std::vector<float> x = room_reverb::test::whiteNoise(n, 9);
    const auto back = fft.inverse(fft.forward(x));
    for (std::size_t t = 0; t < n; ++t) EXPECT_NEAR(back[t], x[t], 1e-5f) << damage << " " << t;
    EXPECT_EQ(readAll(wisdom).rfind("(fftw-", 0), 0u) << damage;
    EXPECT_NE(readAll(wisdom), damage);
  }
  unsetenv("ROOM_REVERB_FFTW_WISDOM");
}

TEST(Convolution, MatchesDirectConvolution) {
  const std::vector<float> a = room_reverb::test::whiteNoise(300, 6);
  const std::vector<float> b = room_reverb::test::whiteNoise(77, 7);
  const std::vector<float> y = fftConvolve(a, b);
  ASSERT_EQ(y.size(), a.size() + b.size() - 1);
  for (std::size_t n = 0; n < y.size(); ++n) {
    double direct = 0.0;
    for (std::size_t k = 0; k < b.size(); ++k) {
      if (n >= k && n - k < a.size()) direct += static_cast<double>(a[n - k]) * b[k];
    }
    EXPECT_NEAR(y[n], direct, 1e-4);
  }
  EXPECT_TRUE(fftConvolve({}, b).empty());
}
