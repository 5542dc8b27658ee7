// Separable filtering row by row, for LDR-FLIP (flip.cpp): a band of output rows is produced in
// order, each from the input rows within the kernels' reach, and nothing the size of the image is
// allocated. Borders repeat the edge pixels (an input row is padded once, and the rows a vertical
// kernel reads are clamped once per output row), so no tap clamps a coordinate.
#pragma once

#include <algorithm>
#include <type_traits>
#include <utility>
#include <vector>

namespace parity::harness::flip {

// A 1D kernel of 2r + 1 taps centred on the pixel; w[i] is the weight at offset +i (i = 0..r).
// Symmetric: the weight at -i is w[i]. Antisymmetric (an edge detector): -w[i], and w[0] is not
// used. ZeroSum (a point detector): symmetric with weights summing to 0, applied to differences
// from the centre sample, so that it gives exactly 0 on a flat region whatever the rounding.
struct Kernel {
  enum Kind { Symmetric, Antisymmetric, ZeroSum };
  Kernel() = default;
  Kernel(std::vector<double> weights, Kind k) : w(std::move(weights)), wf(w.begin(), w.end()), kind(k) {}
  int radius() const { return static_cast<int>(w.size()) - 1; }
  template <class T>
  const T* weights() const {
    if constexpr (std::is_same_v<T, float>) return wf.data();
    else return w.data();
  }
  std::vector<double> w;
  std::vector<float> wf;  // w rounded once, for float samples
  Kind kind = Symmetric;
};

// out[x] = sum over i in -r..r of k(i) * src[i][x], x in [0, n): src[i] points at the samples at
// offset i (a shifted pointer into one padded row along x, another row along y). Folding the taps
// +i and -i halves the multiplies; a block of pixels is summed in registers over all taps, in
// unrolled fixed-length loops that the compiler vectorises at -O2 (SSE2: 4 floats or 2 doubles).
template <Kernel::Kind kind, class T>
void correlateAs(const Kernel& k, const T* const* src, T* out, int n) {
  constexpr int kBlock = 64 / sizeof(T);
  const T* w = k.weights<T>();
  const T* c = src[0];
  const int r = k.radius();
  auto tap = [](T wi, T a, T b, T centre) {
    if constexpr (kind == Kernel::Antisymmetric) return wi * (a - b);
    else if constexpr (kind == Kernel::ZeroSum) return wi * ((a - centre) + (b - centre));
    else return wi * (a + b);
  };
  const T w0 = kind == Kernel::Symmetric ? w[0] : T(0);
  int x = 0;
  for (; x + kBlock <= n; x += kBlock) {
    T acc[kBlock];
#pragma GCC unroll 16
    for (int j = 0; j < kBlock; ++j) acc[j] = w0 * c[x + j];
    for (int i = 1; i <= r; ++i) {
      const T* a = src[i] + x;
      const T* b = src[-i] + x;
      const T wi = w[i];
#pragma GCC unroll 16
      for (int j = 0; j < kBlock; ++j) acc[j] += tap(wi, a[j], b[j], c[x + j]);
    }
#pragma GCC unroll 16
    for (int j = 0; j < kBlock; ++j) out[x + j] = acc[j];
  }
  for (; x < n; ++x) {
    T acc = w0 * c[x];
    for (int i = 1; i <= r; ++i) acc += tap(w[i], src[i][x], src[-i][x], c[x]);
    out[x] = acc;
  }
}

template <class T>
void correlate(const Kernel& k, const T* const* src, T* out, int n) {
  switch (k.kind) {
    case Kernel::Symmetric: return correlateAs<Kernel::Symmetric>(k, src, out, n);
    case Kernel::Antisymmetric: return correlateAs<Kernel::Antisymmetric>(k, src, out, n);
    case Kernel::ZeroSum: return correlateAs<Kernel::ZeroSum>(k, src, out, n);
  }
}

// One separable filter: kernel `alongX` then `alongY` applied to input `input`, or, with yFirst,
// along y first (the same result up to rounding; a derivative taken first sees differences of
// nearby samples instead of differences of sums, which keeps its rounding relative to the detail).
struct SeparablePass {
  int input;
  const Kernel* alongX;
  const Kernel* alongY;
  bool yFirst = false;
};

// The passes of a width x height image, output row by output row. Per pass, the input rows
// filtered along x (or, for yFirst, the padded input rows) are kept in a ring of the last
// 2 * radius + 1 rows; `radius` is the largest of the kernels.
template <class T>
class SeparableRows {
 public:
  SeparableRows(int width, int height, int radius, int inputs, std::vector<SeparablePass> passes)
      : w_(width), h_(height), r_(radius), slots_(2 * radius + 1), passes_(std::move(passes)),
        padded_(inputs, std::vector<T>(width + 2 * radius)), rings_(passes_.size()), out_(passes_.size()),
        scratch_(width + 2 * radius), taps_(slots_) {
    for (size_t p = 0; p < passes_.size(); ++p) {
      rings_[p].resize(static_cast<size_t>(slots_) * rowLength(p));
      out_[p].resize(width);
    }
  }

  // Where the caller writes input row i's width samples before push().
  T* input(int i) { return padded_[i].data() + r_; }

  // Takes in row y, the rows being pushed in order; output(y) needs rows y - radius .. y + radius
  // (those that exist).
  void push(int y) {
    for (std::vector<T>& row : padded_) {
      std::fill(row.begin(), row.begin() + r_, row[r_]);
      std::fill(row.begin() + r_ + w_, row.end(), row[r_ + w_ - 1]);
    }
    for (size_t p = 0; p < passes_.size(); ++p) {
      T* slot = rings_[p].data() + static_cast<size_t>(y % slots_) * rowLength(p);
      const SeparablePass& pass = passes_[p];
      if (pass.yFirst) std::copy(padded_[pass.input].begin(), padded_[pass.input].end(), slot);
      else correlate(*pass.alongX, alongRow(input(pass.input), pass.alongX->radius()), slot, w_);
    }
  }

  // Computes output row y of every pass.
  void output(int y) {
    for (size_t p = 0; p < passes_.size(); ++p) {
      const SeparablePass& pass = passes_[p];
      int ry = pass.alongY->radius();
      for (int i = -ry; i <= ry; ++i)
        taps_[r_ + i] = rings_[p].data() + static_cast<size_t>(std::clamp(y + i, 0, h_ - 1) % slots_) * rowLength(p);
      if (!pass.yFirst) {
        correlate(*pass.alongY, taps_.data() + r_, out_[p].data(), w_);
      } else {  // along y over the padded width, then along x
        correlate(*pass.alongY, taps_.data() + r_, scratch_.data(), w_ + 2 * r_);
        correlate(*pass.alongX, alongRow(scratch_.data() + r_, pass.alongX->radius()), out_[p].data(), w_);
      }
    }
  }

  // Pass p's last output row.
  const T* row(int p) const { return out_[p].data(); }

 private:
  size_t rowLength(size_t p) const { return passes_[p].yFirst ? w_ + 2 * r_ : w_; }
  // The tap pointers of a kernel along a padded row whose pixel 0 is at `centre`.
  const T* const* alongRow(const T* centre, int radius) {
    for (int i = -radius; i <= radius; ++i) taps_[r_ + i] = centre + i;
    return taps_.data() + r_;
  }

  int w_, h_, r_, slots_;
  std::vector<SeparablePass> passes_;
  std::vector<std::vector<T>> padded_;  // each input row with radius edge samples either side
  std::vector<std::vector<T>> rings_;
  std::vector<std::vector<T>> out_;
  std::vector<T> scratch_;
  std::vector<const T*> taps_;  // a kernel's sample pointers, offsets -radius..radius
};

}  // namespace parity::harness::flip
