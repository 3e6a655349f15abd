-- Tests that follow a pattern, as a machine's sequencing does: a flag toggling every cycle,
-- a phase counted round 0..5 and tested for equality, a bit of the cycle number. Each
-- outcome repeats with a short period, which a processor's branch predictor learns: the
-- benchmark shows whether the interpreter lets it (pacer: mb/ and pt/).
local t, ph, a, b, c, d = 0, 0, 0, 0, 0, 0
for i = 1, 6000000 do
  t = 1 - t
  if t == 1 then
    a = a + 1
  else
    b = b + 2
  end
  ph = ph + 1
  if ph == 6 then
    ph = 0
  end
  if ph == 0 then
    c = c + 3
  end
  if i & 4 ~= 0 then
    d = d + 1
  end
end
print(string.format("T=%d A=%d B=%d C=%d D=%d", t, a, b, c, d))
