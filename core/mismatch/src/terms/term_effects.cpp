// Effects from fitted terms (term_effect.h), one layout at a time.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "graftnav/mismatch/term_effect.h"
#include "graftnav/mismatch/term_spec.h"

namespace graftnav {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

EffectParameter columnsParam(const std::string& key, const TermFit& tf, int first, int count) {
  EffectParameter p;
  p.key = key;
  for (int i = 0; i < count; ++i) {
    p.values.push_back(tf.theta(first + i));
    p.sigma.push_back(tf.sigma(first + i));
  }
  return p;
}

// N as a row-major 3 x 3 with zero diagonal; the symmetric variant has one parameter per pair.
EffectParameter crossAxisParam(const std::string& key, const CandidateTerm& term, const TermFit& tf,
                               int first, int* used) {
  EffectParameter p;
  p.key = key;
  p.values.assign(9, 0.0);
  p.sigma.assign(9, 0.0);
  const bool symmetric = term.variant == TermVariant::symmetric;  // N_ij = N_ji
  int k = first;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (i == j || (symmetric && j < i)) continue;
      p.values[i * 3 + j] = tf.theta(k);
      p.sigma[i * 3 + j] = tf.sigma(k);
      if (symmetric) {
        p.values[j * 3 + i] = tf.theta(k);
        p.sigma[j * 3 + i] = tf.sigma(k);
      }
      ++k;
    }
  *used = k - first;
  return p;
}

// Wander of the fitted piecewise-linear bias per axis: its standard deviation over the record.
EffectParameter wanderSdParam(const std::string& key, const CandidateTerm& term, const TermFit& tf,
                              int n_bins) {
  const int per_axis = static_cast<int>(term.columns.size()) / 3;
  EffectParameter p;
  p.key = key;
  const Eigen::MatrixXd path = termContribution(term, tf.theta, n_bins);
  for (int a = 0; a < 3; ++a) {
    const int ch = firstChannel(term.triad()) + a;
    const Eigen::VectorXd v = path.col(ch);
    p.values.push_back(std::sqrt((v.array() - v.mean()).square().mean()));
    double var = 0.0;
    for (int k = 0; k < per_axis; ++k) var += tf.covariance(a * per_axis + k, a * per_axis + k);
    p.sigma.push_back(std::sqrt(var / std::max(1, per_axis)));
  }
  return p;
}

}  // namespace

EffectParameter scalarParam(const std::string& key, double v, double s) {
  EffectParameter p;
  p.key = key;
  p.values = {v};
  p.sigma = {s};
  p.scalar = true;
  return p;
}

Effect effectFromTerm(const CandidateTerm& term, const TermFit& tf, int n_bins) {
  Effect e(*term.spec, term.sensor);
  e.explanation = term.explanation;
  e.delta_bic = tf.delta_bic;
  e.cv_gain = tf.cv_gain;
  std::vector<EffectParameter>& ps = e.parameters;
  int col = 0;  // the next fitted column
  for (const ParameterSpec& spec : term.spec->parameters) {
    switch (spec.layout) {
      case ParameterLayout::per_axis:
        ps.push_back(columnsParam(spec.key, tf, col, 3));
        col += 3;
        break;
      case ParameterLayout::scalar:
        ps.push_back(scalarParam(spec.key, tf.theta(col), tf.sigma(col)));
        col += 1;
        break;
      case ParameterLayout::matrix:
        ps.push_back(columnsParam(spec.key, tf, col, 9));
        col += 9;
        break;
      case ParameterLayout::cross_axis: {
        int used = 0;
        ps.push_back(crossAxisParam(spec.key, term, tf, col, &used));
        col += used;
        break;
      }
      case ParameterLayout::negated: {
        EffectParameter p = ps.back();
        p.key = spec.key;
        for (double& v : p.values) v = -v;
        ps.push_back(p);
        break;
      }
      case ParameterLayout::wander_sd:
        ps.push_back(wanderSdParam(spec.key, term, tf, n_bins));
        col = static_cast<int>(term.columns.size());
        break;
      case ParameterLayout::knot_spacing:
        ps.push_back(scalarParam(spec.key, term.knot_spacing_s, kNaN));
        break;
      case ParameterLayout::reference_temperature:
        ps.push_back(scalarParam(spec.key, term.t_ref_degC, 0.0));
        break;
      case ParameterLayout::regressor_name: {
        EffectParameter r;
        r.key = spec.key;
        r.text = variantName(term.variant);
        ps.push_back(r);
        break;
      }
      case ParameterLayout::set_by_claims:
        break;
    }
  }
  return e;
}

}  // namespace graftnav
