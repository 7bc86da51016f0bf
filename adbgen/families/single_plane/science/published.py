"""Published transients the analysis reproduces (numbers as printed; figures of the thesis ch. 5).

Figure 5.4 (n = 2, parameters (5.1), all initial rates and x, y zero): the thesis reports
r_max = 0.0483, 0.2878, 0.0478 and t_dec = 462.42, 745.02, 549.93 (r < 1e-3) for the initial
ball positions (pi/2, -pi/2), (3pi/4, -3pi/4), (0, pi).  Those runs used Matlab's ode45 at its
default tolerances, so agreement to a few tenths of a percent is what to expect.
"""

from __future__ import annotations

import math

FIGURE_5_4 = {  # panel: (initial (phi_1, phi_2), (r_max, t_dec) as printed)
    "a": ((math.pi / 2, -math.pi / 2), (0.0483, 462.42)),
    "c": ((3 * math.pi / 4, -3 * math.pi / 4), (0.2878, 745.02)),
    "d": ((0.0, math.pi), (0.0478, 549.93)),
}
