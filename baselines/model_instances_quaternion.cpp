// The quaternion models of the library's systems, compiled once (see the explicit instantiation
// declarations at the end of baselines/model.hpp; one file per chart so that they build in
// parallel).
#include "baselines/model.hpp"

namespace lgvi::baselines {

template class CoordinateOde<QuaternionChart, AttitudeMechanics<FreeRigidBody>>;
template class CoordinateOde<QuaternionChart, AttitudeMechanics<Pendulum3D>>;
template class CoordinateOde<QuaternionChart, DumbbellMechanics>;
template class CoordinateOde<QuaternionChart, CartPendulumMechanics>;
template class CoordinateOde<QuaternionChart, ConnectedBodiesMechanics>;

}  // namespace lgvi::baselines
