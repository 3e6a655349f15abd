local n = 40
local a, b, c = {}, {}, {}
for i = 1, n do a[i], b[i], c[i] = {}, {}, {}
  for j = 1, n do a[i][j] = (i + j) / 7; b[i][j] = (i - j) / 3 end end
for r = 1, 30 do
for i = 1, n do
  for j = 1, n do
    local s = 0
    for k = 1, n do s = s + a[i][k] * b[k][j] end
    c[i][j] = s
  end
end
end
local t = 0
for i = 1, n do t = t + c[i][i] + c[i][n + 1 - i] end
print(string.format("%.10g", t))
