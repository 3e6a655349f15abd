-- Arithmetic benchmark: the algorithm of bench.pt in Lua 5.4.
-- pacer keeps Ema and Harm to 6 decimal places, rounding (halves away from zero) on every
-- store; the values here are never negative, so floor(x * 1e6 + 0.5) / 1e6 is that rounding.
local floor = math.floor

local n = 5000000
local acc, hits, odd, chk, mix = 1, 0, 0, 0, 0
local ema, harm = 0.0, 0.0
for i = 1, n do
  -- integer part: a linear congruential walk reduced with MOD
  acc = (acc * 31 + i) % 1000003
  if (acc % 3 == 0) or (acc % 7 == 0) then
    hits = hits + 1
  else
    if acc % 2 == 1 then
      odd = odd + 1
    end
  end
  chk = (chk + acc * 3 + i) % 1000000007
  mix = mix ~ acc
  -- real part: an exponential moving average and the harmonic series
  ema = floor((ema * 0.999 + acc / 1000003) * 1e6 + 0.5) / 1e6
  harm = floor((harm + 1 / i) * 1e6 + 0.5) / 1e6
end

print(string.format("N=%d Acc=%d Hits=%d Odd=%d Chk=%d Mix=%d Ema=%.6f Harm=%.6f",
  n, acc, hits, odd, chk, mix, ema, harm))
