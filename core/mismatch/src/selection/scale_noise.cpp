#include "graftnav/mismatch/scale_noise.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <limits>

namespace graftnav {

HaarEnergies haarEnergies(const Eigen::VectorXd& z) {
  HaarEnergies out;
  std::vector<double> a(z.data(), z.data() + z.size());
  std::vector<double> next;
  const double inv_sqrt2 = 1.0 / std::sqrt(2.0);
  while (a.size() >= 4) {  // the level leaves >= 2 approximation coefficients
    const std::size_t m = a.size() / 2;
    next.resize(m);
    double e = 0.0;
    for (std::size_t k = 0; k < m; ++k) {
      const double d = (a[2 * k] - a[2 * k + 1]) * inv_sqrt2;
      next[k] = (a[2 * k] + a[2 * k + 1]) * inv_sqrt2;
      e += d * d;
    }
    out.energy.push_back(e);
    out.count.push_back(static_cast<int>(m));
    a.swap(next);
  }
  for (double v : a) out.approximation += v * v;
  return out;
}

namespace {

// Hands each level of X's Haar transform (haarCoefficients) to visit(Eigen::MatrixXd&&), finest
// first, holding at most the level being made and the approximation it came from: a level is
// handed on once the next one exists, as the last level also takes the coarsest approximation
// and the odd rows left at each level.
template <class Visit>
void visitHaarLevels(const Eigen::MatrixXd& X, Visit&& visit) {
  std::vector<Eigen::RowVectorXd> leftover;  // odd rows left at each level
  const double inv_sqrt2 = 1.0 / std::sqrt(2.0);
  Eigen::MatrixXd a, pending;
  const Eigen::MatrixXd* cur = &X;
  bool has_pending = false;
  while (cur->rows() >= 4) {
    const Eigen::Index m = cur->rows() / 2;
    if (cur->rows() % 2 != 0) leftover.push_back(cur->row(cur->rows() - 1));
    Eigen::MatrixXd d(m, cur->cols()), next(m, cur->cols());
    for (Eigen::Index k = 0; k < m; ++k) {
      d.row(k) = (cur->row(2 * k) - cur->row(2 * k + 1)) * inv_sqrt2;
      next.row(k) = (cur->row(2 * k) + cur->row(2 * k + 1)) * inv_sqrt2;
    }
    if (has_pending) visit(std::move(pending));
    pending = std::move(d);
    has_pending = true;
    a = std::move(next);
    cur = &a;
  }
  if (!has_pending) {
    visit(Eigen::MatrixXd(X));
    return;
  }
  Eigen::Index m = pending.rows();
  pending.conservativeResize(m + cur->rows() + static_cast<Eigen::Index>(leftover.size()),
                             Eigen::NoChange);
  pending.middleRows(m, cur->rows()) = *cur;
  m += cur->rows();
  for (const Eigen::RowVectorXd& row : leftover) pending.row(m++) = row;
  visit(std::move(pending));
}

}  // namespace

std::vector<Eigen::MatrixXd> haarCoefficients(const Eigen::MatrixXd& X) {
  std::vector<Eigen::MatrixXd> out;
  visitHaarLevels(X, [&](Eigen::MatrixXd&& level) { out.push_back(std::move(level)); });
  return out;
}

std::vector<Eigen::MatrixXd> haarLevelGrams(const Eigen::MatrixXd& X) {
  std::vector<Eigen::MatrixXd> grams;
  visitHaarLevels(X, [&](Eigen::MatrixXd&& D) { grams.push_back(D.transpose() * D); });
  return grams;
}

namespace {
constexpr Eigen::Index kHaarBufferRows = 256;
}

// The levels of visitHaarLevels: a level pairs its rows while it has at least 4; an odd last
// row and the final approximation's rows join the last level.
HaarLevelGramAccumulator::HaarLevelGramAccumulator(Eigen::Index rows, Eigen::Index cols)
    : cols_(cols), levels_(0) {
  if (rows < 1 || cols < 1)
    throw std::invalid_argument("HaarLevelGramAccumulator: rows and cols must be >= 1");
  size_.push_back(rows);
  while (size_.back() >= 4) {
    size_.push_back(size_.back() / 2);
    ++levels_;
  }
  seen_.assign(size_.size(), 0);
  unpaired_.assign(size_.size(), Eigen::RowVectorXd::Zero(cols));
  const int grams = std::max(1, levels_);
  buffer_.assign(grams, Eigen::MatrixXd(kHaarBufferRows, cols));
  buffered_.assign(grams, 0);
  gram_.assign(grams, Eigen::MatrixXd::Zero(cols, cols));
}

void HaarLevelGramAccumulator::add(const Eigen::Ref<const Eigen::MatrixXd>& block) {
  if (block.cols() != cols_ || added_ + block.rows() > size_[0])
    throw std::invalid_argument("HaarLevelGramAccumulator: block beyond the rows or columns");
  added_ += block.rows();
  for (Eigen::Index i = 0; i < block.rows(); ++i) feed(0, block.row(i));
}

void HaarLevelGramAccumulator::feed(int level, const Eigen::Ref<const Eigen::RowVectorXd>& row) {
  const int last = std::max(0, levels_ - 1);
  if (level == levels_) {  // the final approximation (or X itself below 4 rows)
    addToGram(last, row);
    return;
  }
  const Eigen::Index k = seen_[level]++;
  if (k == size_[level] - 1 && size_[level] % 2 != 0) {  // the odd row left over
    addToGram(last, row);
  } else if (k % 2 == 0) {
    unpaired_[level] = row;
  } else {
    const double inv_sqrt2 = 1.0 / std::sqrt(2.0);
    addToGram(level, (unpaired_[level] - row) * inv_sqrt2);
    feed(level + 1, (unpaired_[level] + row) * inv_sqrt2);
  }
}

void HaarLevelGramAccumulator::addToGram(int level,
                                         const Eigen::Ref<const Eigen::RowVectorXd>& row) {
  buffer_[level].row(buffered_[level]++) = row;
  if (buffered_[level] == kHaarBufferRows) flush(level);
}

void HaarLevelGramAccumulator::flush(int level) {
  const auto B = buffer_[level].topRows(buffered_[level]);
  gram_[level] += B.transpose() * B;
  buffered_[level] = 0;
}

std::vector<Eigen::MatrixXd> HaarLevelGramAccumulator::grams() {
  if (added_ != size_[0])
    throw std::logic_error("HaarLevelGramAccumulator: grams asked before every row was added");
  for (std::size_t j = 0; j < gram_.size(); ++j) flush(static_cast<int>(j));
  return gram_;
}

Eigen::MatrixXd haarSynthesis(const std::vector<Eigen::MatrixXd>& levels, Eigen::Index rows) {
  if (levels.empty()) throw std::invalid_argument("haarSynthesis: no levels");
  // The forward pass's sizes: rows at each step and whether a row was left over.
  std::vector<Eigen::Index> sizes;
  for (Eigen::Index r = rows; r >= 4; r /= 2) sizes.push_back(r);
  if (sizes.size() != levels.size() && !(sizes.empty() && levels.size() == 1))
    throw std::invalid_argument("haarSynthesis: " + std::to_string(levels.size()) +
                                " levels do not match " + std::to_string(rows) + " rows");
  if (sizes.empty()) return levels[0];
  const Eigen::Index cols = levels[0].cols();
  const double inv_sqrt2 = 1.0 / std::sqrt(2.0);
  // The last level: its details, the final approximation, then the left-over rows in the order
  // the forward pass met them.
  const Eigen::MatrixXd& last = levels.back();
  const Eigen::Index m_last = sizes.back() / 2;
  const Eigen::Index n_approx = m_last;
  std::vector<Eigen::Index> odd_steps;
  for (std::size_t k = 0; k < sizes.size(); ++k)
    if (sizes[k] % 2 != 0) odd_steps.push_back(static_cast<Eigen::Index>(k));
  if (last.rows() != m_last + n_approx + static_cast<Eigen::Index>(odd_steps.size()))
    throw std::invalid_argument("haarSynthesis: last level has the wrong number of rows");
  Eigen::MatrixXd a = last.middleRows(m_last, n_approx);
  for (std::size_t k = sizes.size(); k-- > 0;) {
    const Eigen::Index n_k = sizes[k], m = n_k / 2;
    const Eigen::MatrixXd d =
        k + 1 == sizes.size() ? Eigen::MatrixXd(last.topRows(m_last)) : levels[k];
    Eigen::MatrixXd x(n_k, cols);
    for (Eigen::Index i = 0; i < m; ++i) {
      x.row(2 * i) = (a.row(i) + d.row(i)) * inv_sqrt2;
      x.row(2 * i + 1) = (a.row(i) - d.row(i)) * inv_sqrt2;
    }
    if (n_k % 2 != 0) {
      const auto pos = std::find(odd_steps.begin(), odd_steps.end(), static_cast<Eigen::Index>(k));
      x.row(n_k - 1) = last.row(m_last + n_approx + (pos - odd_steps.begin()));
    }
    a.swap(x);
  }
  return a;
}

double ScaleNoiseModel::at(int level) const {
  const int j = std::clamp(level, 1, std::max(1, levels));
  return 1.0 + a * std::ldexp(1.0, j) + b * std::ldexp(1.0, 2 * j);
}

ScaleNoiseModel fitScaleNoise(const HaarEnergies& r, double unit_variance, int max_fit_level) {
  ScaleNoiseModel m;
  m.levels = static_cast<int>(r.energy.size());
  const int n = max_fit_level > 0 ? std::min(m.levels, max_fit_level) : m.levels;
  if (n == 0 || !(unit_variance > 0.0)) return m;
  std::vector<double> v(n), x(n), y(n), c(n);
  for (int j = 1; j <= n; ++j) {
    v[j - 1] = r.count[j - 1] > 0 ? r.energy[j - 1] / r.count[j - 1] / unit_variance : 1.0;
    x[j - 1] = std::ldexp(1.0, j) / std::ldexp(1.0, n);  // columns scaled to <= 1
    y[j - 1] = std::ldexp(1.0, 2 * j) / std::ldexp(1.0, 2 * n);
    c[j - 1] = std::max(1.0, v[j - 1]);
  }
  double ax = 0.0, by = 0.0;  // coefficients of the scaled columns
  // Iteratively reweighted least squares: weights n_j / c_j^2 with c_j from the last fit.
  for (int it = 0; it < 8; ++it) {
    double sxx = 0.0, syy = 0.0, sxy = 0.0, sxv = 0.0, syv = 0.0;
    for (int j = 0; j < n; ++j) {
      const double w = r.count[j] / (c[j] * c[j]);
      const double d = v[j] - 1.0;
      sxx += w * x[j] * x[j];
      syy += w * y[j] * y[j];
      sxy += w * x[j] * y[j];
      sxv += w * x[j] * d;
      syv += w * y[j] * d;
    }
    const auto sse = [&](double p, double q) {
      double s = 0.0;
      for (int j = 0; j < n; ++j) {
        const double e = v[j] - 1.0 - p * x[j] - q * y[j];
        s += r.count[j] / (c[j] * c[j]) * e * e;
      }
      return s;
    };
    // Non-negative least squares in two unknowns: the joint solution if both are >= 0, else
    // the better of the two one-parameter fits (each clamped at 0).
    const double det = sxx * syy - sxy * sxy;
    double p = -1.0, q = -1.0;
    if (det > 1e-12 * sxx * syy) {
      p = (syy * sxv - sxy * syv) / det;
      q = (sxx * syv - sxy * sxv) / det;
    }
    if (!(p >= 0.0 && q >= 0.0)) {
      const double p1 = sxx > 0.0 ? std::max(0.0, sxv / sxx) : 0.0;
      const double q1 = syy > 0.0 ? std::max(0.0, syv / syy) : 0.0;
      if (sse(p1, 0.0) <= sse(0.0, q1)) {
        p = p1;
        q = 0.0;
      } else {
        p = 0.0;
        q = q1;
      }
    }
    ax = p;
    by = q;
    for (int j = 0; j < n; ++j) c[j] = 1.0 + ax * x[j] + by * y[j];
  }
  m.a = ax / std::ldexp(1.0, n);
  m.b = by / std::ldexp(1.0, 2 * n);
  return m;
}

}  // namespace graftnav
