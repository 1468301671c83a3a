// The euler models of the library's systems, compiled once (see the explicit instantiation
// declarations at the end of baselines/model.hpp; one file per chart so that they build in
// parallel).
#include "baselines/model.hpp"

namespace lgvi::baselines {

template class CoordinateOde<EulerChart, AttitudeMechanics<FreeRigidBody>>;
template class CoordinateOde<EulerChart, AttitudeMechanics<Pendulum3D>>;
template class CoordinateOde<EulerChart, DumbbellMechanics>;
template class CoordinateOde<EulerChart, CartPendulumMechanics>;
template class CoordinateOde<EulerChart, ConnectedBodiesMechanics>;

}  // namespace lgvi::baselines
