// Small numeric helpers: divisions that cannot produce inf/NaN.
#ifndef NUMERIC_GLSL
#define NUMERIC_GLSL

const float TINY = 1e-20;

// a / b with b pushed away from zero, keeping its sign.
float safe_div(float a, float b) {
    return a / (abs(b) < TINY ? (b < 0.0 ? -TINY : TINY) : b);
}

#endif

// Smallest t in [0, t_max] where A t^2 + B t + C first reaches 0 from below (C < 0), with the
// cancellation-free form of the roots: q = -(B + sign(B) sqrt(disc)) / 2, roots q/A and C/q.
bool first_root(float A, float B, float C, float t_max, out float t) {
    t = t_max;
    float disc = B * B - 4.0 * A * C;
    if (disc < 0.0) {
        return false;
    }
    float q = -0.5 * (B + (B < 0.0 ? -1.0 : 1.0) * sqrt(disc));
    float r1 = abs(A) > TINY ? q / A : 3.0e38;
    float r2 = abs(q) > TINY ? C / q : 3.0e38;
    float lo = min(r1, r2);
    float hi = max(r1, r2);
    float root = lo >= 0.0 ? lo : hi;
    if (root >= 0.0 && root <= t_max) {
        t = root;
        return true;
    }
    // Rounding can push a root that touches the interval's end just outside it.
    if (A * t_max * t_max + B * t_max + C >= 0.0) {
        return true;
    }
    return false;
}
