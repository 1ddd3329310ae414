"""The constants of rrbody's two Runge-Kutta methods, written out here (not loaded from scipy at run time).

- **DOP853** (Dormand and Prince's explicit 8(5,3) pair): the coefficients of E. Hairer's ``dop853.f``
  (Hairer, Norsett and Wanner, *Solving Ordinary Differential Equations I*, 2nd ed., Springer 1993,
  section II.10), as scipy carries them in ``scipy/integrate/_ivp/dop853_coefficients.py`` (BSD-3-Clause),
  copied digit for digit: the nodes ``C``, the stages 1-12 of ``A`` (row 12 is the weights ``B``), and the
  error weights ``E3`` and ``E5``. Only the 12 stages of a step and the 13th evaluation (f at the new
  point) are used: rrbody's dense output is its own (``rrbody.integrate.loop``), not DOP853's 16-stage one.
- **Radau IIA** of order 5 (three stages): the nodes, the embedded error estimate of RADAU5, the
  eigen-decomposition of the stage matrix (one real and a complex pair, Hairer and Wanner, *Solving
  Ordinary Differential Equations II*, section IV.8) and the collocation polynomial's coefficients, as
  scipy writes them in ``scipy/integrate/_ivp/radau.py`` (BSD-3-Clause), copied expression for expression.

``tests/test_tableaus.py`` compares every array here with scipy's own, bit for bit, on the scipy the suite
runs (the newest and the oldest pyproject allows). Before, these were read from scipy's private files at
import (the DOP853 module loaded by path, the Radau block ``exec``-ed from its source text): a scipy that
moved or reworded them would have broken every import of ``rrbody.integrate``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["DOP853_STAGES", "DOP853_C", "DOP853_A", "DOP853_B", "DOP853_E3", "DOP853_E5",
           "RADAU_C", "RADAU_E", "RADAU_MU_REAL", "RADAU_MU_COMPLEX", "RADAU_T", "RADAU_TI", "RADAU_P"]

# ---- DOP853 (Hairer's dop853.f; scipy/integrate/_ivp/dop853_coefficients.py) ----

#: stages of one step (a 13th evaluation, f at the new point, is the first stage of the next step)
DOP853_STAGES: int = 12

# the nodes of all 16 stages of scipy's table (only the first 12 are used: see below)
_C16 = np.array([0.0,
                  0.526001519587677318785587544488e-01,
                  0.789002279381515978178381316732e-01,
                  0.118350341907227396726757197510,
                  0.281649658092772603273242802490,
                  0.333333333333333333333333333333,
                  0.25,
                  0.307692307692307692307692307692,
                  0.651282051282051282051282051282,
                  0.6,
                  0.857142857142857142857142857142,
                  1.0,
                  1.0,
                  0.1,
                  0.2,
                  0.777777777777777777777777777778])

# rows 1-12 of the stage matrix (row 12: the weights B); every entry not assigned is 0
_A = np.zeros((DOP853_STAGES + 1, DOP853_STAGES))
_A[1, 0] = 5.26001519587677318785587544488e-2
_A[2, 0] = 1.97250569845378994544595329183e-2
_A[2, 1] = 5.91751709536136983633785987549e-2
_A[3, 0] = 2.95875854768068491816892993775e-2
_A[3, 2] = 8.87627564304205475450678981324e-2
_A[4, 0] = 2.41365134159266685502369798665e-1
_A[4, 2] = -8.84549479328286085344864962717e-1
_A[4, 3] = 9.24834003261792003115737966543e-1
_A[5, 0] = 3.7037037037037037037037037037e-2
_A[5, 3] = 1.70828608729473871279604482173e-1
_A[5, 4] = 1.25467687566822425016691814123e-1
_A[6, 0] = 3.7109375e-2
_A[6, 3] = 1.70252211019544039314978060272e-1
_A[6, 4] = 6.02165389804559606850219397283e-2
_A[6, 5] = -1.7578125e-2
_A[7, 0] = 3.70920001185047927108779319836e-2
_A[7, 3] = 1.70383925712239993810214054705e-1
_A[7, 4] = 1.07262030446373284651809199168e-1
_A[7, 5] = -1.53194377486244017527936158236e-2
_A[7, 6] = 8.27378916381402288758473766002e-3
_A[8, 0] = 6.24110958716075717114429577812e-1
_A[8, 3] = -3.36089262944694129406857109825
_A[8, 4] = -8.68219346841726006818189891453e-1
_A[8, 5] = 2.75920996994467083049415600797e1
_A[8, 6] = 2.01540675504778934086186788979e1
_A[8, 7] = -4.34898841810699588477366255144e1
_A[9, 0] = 4.77662536438264365890433908527e-1
_A[9, 3] = -2.48811461997166764192642586468
_A[9, 4] = -5.90290826836842996371446475743e-1
_A[9, 5] = 2.12300514481811942347288949897e1
_A[9, 6] = 1.52792336328824235832596922938e1
_A[9, 7] = -3.32882109689848629194453265587e1
_A[9, 8] = -2.03312017085086261358222928593e-2
_A[10, 0] = -9.3714243008598732571704021658e-1
_A[10, 3] = 5.18637242884406370830023853209
_A[10, 4] = 1.09143734899672957818500254654
_A[10, 5] = -8.14978701074692612513997267357
_A[10, 6] = -1.85200656599969598641566180701e1
_A[10, 7] = 2.27394870993505042818970056734e1
_A[10, 8] = 2.49360555267965238987089396762
_A[10, 9] = -3.0467644718982195003823669022
_A[11, 0] = 2.27331014751653820792359768449
_A[11, 3] = -1.05344954667372501984066689879e1
_A[11, 4] = -2.00087205822486249909675718444
_A[11, 5] = -1.79589318631187989172765950534e1
_A[11, 6] = 2.79488845294199600508499808837e1
_A[11, 7] = -2.85899827713502369474065508674
_A[11, 8] = -8.87285693353062954433549289258
_A[11, 9] = 1.23605671757943030647266201528e1
_A[11, 10] = 6.43392746015763530355970484046e-1
_A[12, 0] = 5.42937341165687622380535766363e-2
_A[12, 5] = 4.45031289275240888144113950566
_A[12, 6] = 1.89151789931450038304281599044
_A[12, 7] = -5.8012039600105847814672114227
_A[12, 8] = 3.1116436695781989440891606237e-1
_A[12, 9] = -1.52160949662516078556178806805e-1
_A[12, 10] = 2.01365400804030348374776537501e-1
_A[12, 11] = 4.47106157277725905176885569043e-2

DOP853_C: np.ndarray = np.ascontiguousarray(_C16[:DOP853_STAGES])
DOP853_A: np.ndarray = np.ascontiguousarray(_A[:DOP853_STAGES])
DOP853_B: np.ndarray = np.ascontiguousarray(_A[DOP853_STAGES])

# the 3rd- and 5th-order error weights (13 entries: the 13th multiplies f at the new point)
DOP853_E3: np.ndarray = np.zeros(DOP853_STAGES + 1)
DOP853_E3[:-1] = DOP853_B
DOP853_E3[0] -= 0.244094488188976377952755905512
DOP853_E3[8] -= 0.733846688281611857341361741547
DOP853_E3[11] -= 0.220588235294117647058823529412e-1
DOP853_E5: np.ndarray = np.zeros(DOP853_STAGES + 1)
DOP853_E5[0] = 0.1312004499419488073250102996e-1
DOP853_E5[5] = -0.1225156446376204440720569753e+1
DOP853_E5[6] = -0.4957589496572501915214079952
DOP853_E5[7] = 0.1664377182454986536961530415e+1
DOP853_E5[8] = -0.3503288487499736816886487290
DOP853_E5[9] = 0.3341791187130174790297318841
DOP853_E5[10] = 0.8192320648511571246570742613e-1
DOP853_E5[11] = -0.2235530786388629525884427845e-1

# ---- Radau IIA, order 5 (scipy/integrate/_ivp/radau.py) ----

_S6 = 6 ** 0.5
#: the collocation nodes
RADAU_C: np.ndarray = np.array([(4 - _S6) / 10, (4 + _S6) / 10, 1])
#: the embedded error estimate's weights (RADAU5)
RADAU_E: np.ndarray = np.array([-13 - 7 * _S6, -13 + 7 * _S6, -1]) / 3
#: the stage matrix A = T diag(MU_REAL, MU_COMPLEX, conj(MU_COMPLEX)) T^-1 (the eigenvalues of A^-1)
RADAU_MU_REAL: float = 3 + 3 ** (2 / 3) - 3 ** (1 / 3)
RADAU_MU_COMPLEX: complex = (3 + 0.5 * (3 ** (1 / 3) - 3 ** (2 / 3))
                             - 0.5j * (3 ** (5 / 6) + 3 ** (7 / 6)))
RADAU_T: np.ndarray = np.array([
    [0.09443876248897524, -0.14125529502095421, 0.03002919410514742],
    [0.25021312296533332, 0.20412935229379994, -0.38294211275726192],
    [1, 1, 0]])
RADAU_TI: np.ndarray = np.array([
    [4.17871859155190428, 0.32768282076106237, 0.52337644549944951],
    [-4.17871859155190428, -0.32768282076106237, 0.47662355450055044],
    [0.50287263494578682, -2.57192694985560522, 0.59603920482822492]])
#: the collocation polynomial: Z(s) = sum_q (Z^T P)_q s^(q+1), s in units of the step
RADAU_P: np.ndarray = np.array([
    [13/3 + 7*_S6/3, -23/3 - 22*_S6/3, 10/3 + 5 * _S6],
    [13/3 - 7*_S6/3, -23/3 + 22*_S6/3, 10/3 - 5 * _S6],
    [1/3, -8/3, 10/3]])
