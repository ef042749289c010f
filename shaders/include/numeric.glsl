// Small numeric helpers: divisions that cannot produce inf/NaN.
#ifndef NUMERIC_GLSL
#define NUMERIC_GLSL

const float TINY = 1e-20;

// a / b with b pushed away from zero, keeping its sign.
float safe_div(float a, float b) {
    return a / (abs(b) < TINY ? (b < 0.0 ? -TINY : TINY) : b);
}

#endif
