local a, b = {}, {}
for i = 0, 100 do a[i] = i * 0.5; b[i] = 100 - i end
local s = 0.0
for r = 1, 300 do
  for i = 0, 100 do
    for j = 0, 100 do
      s = s + a[i] * b[j] * 0.001
    end
  end
end
print(s)
