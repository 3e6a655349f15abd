local s = 0
for i = 1, 600 do
  for j = 1, 600 do
    local a, b = i, j
    while b ~= 0 do
      a, b = b, a % b
    end
    s = s + a
  end
end
print(s)
