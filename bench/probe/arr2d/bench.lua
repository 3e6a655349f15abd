local g = {}
for i = 0, 50 do g[i] = {} end
local s = 0
for r = 1, 400 do
for i = 0, 50 do
  for j = 0, 50 do
    g[i][j] = (i * j + r) % 97
  end
end
for i = 1, 50 do
  for j = 1, 50 do
    s = s + g[i][j] - g[i-1][j-1]
  end
end
end
print(s)
