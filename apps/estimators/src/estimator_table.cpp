#include "graftnav/estimators/estimator_table.h"

#include "graftnav/filters/filter_estimators.h"
#include "graftnav/graph/graph_estimators.h"

namespace graftnav {

const EstimatorRegistry& estimatorTable() {
  static const EstimatorRegistry table = [] {
    EstimatorRegistry r;
    addFilterEstimators(&r);
    addGraphEstimators(&r);
    return r;
  }();
  return table;
}

}  // namespace graftnav
