// The matrix models of the library's systems, compiled once (see the explicit instantiation
// declarations at the end of baselines/model.hpp; one file per chart so that they build in
// parallel).
#include "baselines/model.hpp"

namespace lgvi::baselines {

template class CoordinateOde<MatrixChart, AttitudeMechanics<FreeRigidBody>>;
template class CoordinateOde<MatrixChart, AttitudeMechanics<Pendulum3D>>;
template class CoordinateOde<MatrixChart, DumbbellMechanics>;
template class CoordinateOde<MatrixChart, CartPendulumMechanics>;
template class CoordinateOde<MatrixChart, ConnectedBodiesMechanics>;

}  // namespace lgvi::baselines
