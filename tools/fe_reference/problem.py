"""The sphere scene and Hertz's solution for it (METHOD.md section 7).

Elastic sphere, radius R, centre at the origin, pressed with a total force P
against a rigid plane z = -R (the contact centre is the south pole (0, 0, -R)), or against
a rigid ball of radius `ball` touching it there (1/R* = 1/R + 1/ball).
"""
import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Problem:
    radius: float = 1.0          # R, m
    youngs: float = 1.0e9        # E, Pa
    poisson: float = 0.25        # nu
    contact_radius: float = 0.15  # Hertz a, m; the load P follows from it
    ball: float = 0.0            # radius of the rigid ball in place of the plane (0: the plane)

    @property
    def r_star(self) -> float:
        """R* of the pair: R on the plane, 1/(1/R + 1/ball) on a ball."""
        return 1.0 / (1.0 / self.radius + 1.0 / self.ball) if self.ball > 0.0 else self.radius

    def sag(self, r):
        """How far the ball's surface falls below the plane z = -R at the distance r from
        the axis (0 for the plane)."""
        if self.ball <= 0.0:
            return 0.0 * r
        return self.ball - (self.ball ** 2 - r ** 2) ** 0.5

    @property
    def e_star(self) -> float:
        """E* of an elastic body on a rigid one: E / (1 - nu^2)."""
        return self.youngs / (1.0 - self.poisson ** 2)

    @property
    def load(self) -> float:
        """P such that a = (3PR*/(4E*))^(1/3)."""
        return 4.0 * self.e_star * self.contact_radius ** 3 / (3.0 * self.r_star)

    @property
    def p0(self) -> float:
        """Peak pressure 3P/(2 pi a^2)."""
        return 3.0 * self.load / (2.0 * math.pi * self.contact_radius ** 2)

    @property
    def approach(self) -> float:
        """Hertz approach a^2/R* of the plane (ball) towards distant points of the sphere."""
        return self.contact_radius ** 2 / self.r_star

    def pressure(self, r: float) -> float:
        """p(r) = p0 sqrt(1 - (r/a)^2), zero outside the contact."""
        s = 1.0 - (r / self.contact_radius) ** 2
        return self.p0 * math.sqrt(s) if s > 0.0 else 0.0
